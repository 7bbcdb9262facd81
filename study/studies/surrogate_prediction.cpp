// See surrogate_prediction.hpp.
#include "study/studies/surrogate_prediction.hpp"
#include "core/number_text.hpp"
#include "study/estimators/work_stopped.hpp"
#include "study/studies/report_format.hpp"

#include <algorithm>
#include <sstream>

#include "io/json_reader.hpp"

namespace rover::study {
namespace {

std::string input_list(const SurrogateSet& set) {
  std::string out;
  for (const SurrogateInput& in : set.inputs) out += (out.empty() ? "" : ", ") + in.label;
  return out;
}


// The surrogate input of each design column.
std::vector<std::size_t> column_inputs(const SurrogateSet& set, const DesignTable& design) {
  std::vector<std::size_t> input_of(design.columns.size());
  std::vector<bool> seen(set.inputs.size(), false);
  for (std::size_t c = 0; c < design.columns.size(); ++c) {
    const std::string& column = design.columns[c];
    const auto it = std::find_if(set.inputs.begin(), set.inputs.end(), [&](const SurrogateInput& in) {
      return column == in.label || column == in.name;
    });
    const std::string where = design.path + ":" + std::to_string(design.header_line) + ": column " +
                              std::to_string(c + 1) + " '" + column + "'";
    if (it == set.inputs.end())
      throw io::ConfigError(where + " is not an input of the surrogate (its inputs: " + input_list(set) + ")");
    const auto j = static_cast<std::size_t>(it - set.inputs.begin());
    if (seen[j]) throw io::ConfigError(where + " repeats input '" + it->label + "'");
    seen[j] = true;
    input_of[c] = j;
  }
  for (std::size_t j = 0; j < set.inputs.size(); ++j)
    if (!seen[j])
      throw io::ConfigError(design.path + ": no column for input '" + set.inputs[j].label +
                            "' of the surrogate (its inputs: " + input_list(set) + ")");
  return input_of;
}

}  // namespace

DesignTable read_surrogate_design(const SurrogateSet& set, const std::string& path) {
  return read_design_csv(path, [&](const DesignTable& header) { (void)column_inputs(set, header); });
}

DesignMatrix surrogate_points(const SurrogateSet& set, const DesignTable& design) {
  const std::vector<std::size_t> input_of = column_inputs(set, design);
  DesignMatrix x(design.values.rows(), static_cast<Eigen::Index>(set.inputs.size()));
  for (Eigen::Index i = 0; i < design.values.rows(); ++i) {
    for (std::size_t c = 0; c < input_of.size(); ++c) {
      const SurrogateInput& in = set.inputs[input_of[c]];
      const double v = design.values(i, static_cast<Eigen::Index>(c));
      if (!(v >= in.lower && v <= in.upper))
        throw io::ConfigError(design.path + ":" + std::to_string(design.line_numbers[static_cast<std::size_t>(i)]) +
                              ": row " + std::to_string(i + 1) + ": " + in.label + " = " + number_text(v) +
                              " lies outside the training support [" + number_text(in.lower) + ", " + number_text(in.upper) +
                              "]" + (in.support_note.empty() ? "" : " (" + in.support_note + ")") +
                              "; a surrogate is not extrapolated");
      x(i, static_cast<Eigen::Index>(input_of[c])) = v;
    }
  }
  return x;
}

namespace {

// The predictions of `m` at the rows of x, kPredictionChunkRows at a time,
// `stop` read before each chunk.
constexpr Eigen::Index kPredictionChunkRows = 16384;
SurrogatePrediction predict_in_chunks(const FittedSurrogate& m, const DesignMatrix& x,
                                      const std::atomic<bool>* stop) {
  SurrogatePrediction all;
  all.mean.resize(x.rows());
  if (m.kind == SurrogateKind::kGaussianProcess) all.sd.resize(x.rows());
  for (Eigen::Index first = 0; first < x.rows(); first += kPredictionChunkRows) {
    stop_if_requested(stop, "surrogate: prediction");
    const Eigen::Index n = std::min(kPredictionChunkRows, x.rows() - first);
    const SurrogatePrediction p = predict_surrogate(m, x.middleRows(first, n));
    all.mean.segment(first, n) = p.mean;
    if (all.sd.size() == x.rows() && p.sd.size() == n) all.sd.segment(first, n) = p.sd;
  }
  return all;
}

}  // namespace

PredictionTable predict_surrogate_set(const SurrogateSet& set, const DesignMatrix& x, const std::atomic<bool>* stop) {
  PredictionTable table;
  for (std::size_t j = 0; j < set.inputs.size(); ++j) {
    table.header.push_back(set.inputs[j].label);
    table.columns.push_back(to_vector(x.col(static_cast<Eigen::Index>(j))));
  }
  for (const FittedSurrogate& m : set.models) {
    const SurrogatePrediction p = predict_in_chunks(m, x, stop);
    table.header.push_back(m.output_name());
    table.columns.push_back(to_vector(p.mean));
    if (m.kind != SurrogateKind::kGaussianProcess) continue;
    table.header.push_back(m.output_name() + "_sd");
    table.columns.push_back(to_vector(p.sd));
  }
  return table;
}

}  // namespace rover::study
