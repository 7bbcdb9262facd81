// Predictions of a saved surrogate set at new points (`rover surrogate
// --predict model.h5 --design X.csv --csv Y.csv`): the design CSV of `rover
// evaluate` (a header of parameter names, one row per point), its columns
// matched to the surrogate's inputs by label or canonical name, every point
// checked against the training support before anything is predicted. The
// table has the inputs, then per QoI its predicted mean and, for a Gaussian
// process, its predictive standard deviation (<qoi>_sd).
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include "study/studies/evaluate.hpp"
#include "study/studies/surrogate_file.hpp"

namespace rover::study {

// The design's points in the order of the set's inputs. Throws
// io::ConfigError naming the design file for a column that is not an input
// of the surrogate, an input without a column, and a point outside the
// training support (naming its row, line, parameter and the support).
DesignMatrix surrogate_points(const SurrogateSet& set, const DesignTable& design);

// The design CSV at `path`, its header checked against the set's inputs
// before any value is read (a column that is no input is named first).
DesignTable read_surrogate_design(const SurrogateSet& set, const std::string& path);

struct PredictionTable {
  std::vector<std::string> header;
  std::vector<std::vector<double>> columns;  // columns[j][point]
};

// Throws WorkStopped once `stop` (if given; read every few thousand points)
// is set.
PredictionTable predict_surrogate_set(const SurrogateSet& set, const DesignMatrix& x,
                                      const std::atomic<bool>* stop = nullptr);

}  // namespace rover::study
