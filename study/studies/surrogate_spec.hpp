// The surrogate study (`rover surrogate --study S.json`): which runs train a
// surrogate of which QoIs, of which kind, and how it is validated.
//
// Study file: the keys of study_spec.hpp ("scenario" or "model", "parameters",
// "qoi"; "channels" are not taken), with
//   "type": "surrogate",
//   "surrogate": "pce" | "gp"                       (default "pce"),
//   the training runs, one of
//     "design": {"type": "lhs", "samples": N, "seed": s}   runs made now: any design
//               of the study core ("type" defaults to "latin_hypercube", "lhs" is its alias)
//     "training": {"file": "results/mc.h5"}        the runs of a result file of
//               montecarlo, evaluate, sensitivity or surrogate (relative to the study file),
//   "held_out": {"fraction": 0.2} (the last runs, design or file, in (0, 0.5])
//               or {"file": "results/other.h5"}     optional held-out validation
//               of at least 2 runs (a Q2 needs the spread of 2 values),
//   "pce": {"max_degree": 12, "q_norm": 0.75, "bootstrap": 200, "q2_threshold": 0.95},
//   "gp":  {"trend": "constant" | "linear", "starts": 4, "nugget": 1e-8 | "estimate",
//           "q2_threshold": 0.95},
//   "confidence": 0.95                               (of the bootstrap intervals),
//   "compare": {"file": "results/sobol_drop.h5"}     optional: a sensitivity result
//               whose total indices the PCE's are plotted beside.
//
// Every listed parameter must vary (no "fixed" distribution): it is an input
// of the surrogate. Too few training runs for the requested basis or trend
// are refused here, before any run.
#pragma once

#include <string>
#include <vector>

#include "study/studies/pce_sensitivity.hpp"
#include "study/studies/study_spec.hpp"
#include "study/surrogate/fitted_surrogate.hpp"
#include "study/surrogate/gaussian_process.hpp"

namespace rover::study {

inline constexpr double kMaxHeldOutFraction = 0.5;

struct SurrogateStudy {
  StudySpec spec;  // the model, the inputs and, without a training file, the design
  SurrogateKind kind = SurrogateKind::kPolynomialChaos;
  PceSensitivityOptions pce;    // basis, bootstrap, confidence, seed
  GaussianProcessSettings gp;
  std::string training_file;    // empty: the design is run
  double held_out_fraction = 0.0;
  std::string held_out_file;    // empty: none, or the held-out fraction of the design
  std::string compare_file;     // empty: none; a sensitivity result to plot beside

  double q2_threshold() const;
  std::vector<std::string> qoi_names() const;
  std::vector<Distribution> distributions() const;
  // The design's runs held out for validation (0 with a training file).
  int held_out_runs() const;
};

// Reads and checks a study file; errors are io::ConfigErrors naming the file
// and the field.
SurrogateStudy load_surrogate_study(const std::string& path, const DesignOverrides& overrides = {});

// The fewest training runs the fit accepts (after failed and held-out runs are removed).
int min_training_runs(const SurrogateStudy& study);

// Why `fraction` of `runs` runs holds out too few runs for a held-out Q2
// (kMinHeldOutRuns), naming the count and the least fraction; "" if enough.
std::string held_out_count_problem(double fraction, long long runs);

// The QoIs of `study` whose total indices over all of its inputs its
// "compare" file lacks (/indices/<qoi>/ST, /inputs/names). Throws what
// reading the file throws.
std::vector<std::string> qois_without_compared_indices(const SurrogateStudy& study);

// --samples: the design's run count. Throws std::invalid_argument for a study
// trained on a file, or too few runs for the fit or for the held-out Q2.
void set_surrogate_runs(SurrogateStudy& study, int runs);

}  // namespace rover::study
