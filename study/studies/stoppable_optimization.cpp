// See stoppable_optimization.hpp.
#include "study/studies/stoppable_optimization.hpp"

#include "study/estimators/work_stopped.hpp"
#include "study/runtime/study_runner.hpp"

namespace rover::study {
namespace {

struct StoppableObjective {
  const SearchObjective& objective;
  bool stopped = false;
};

double evaluate_stoppably(const std::vector<double>& x, std::vector<double>& /*grad*/, void* data) {
  auto& s = *static_cast<StoppableObjective*>(data);
  try {
    stop_if_requested(&InterruptGuard::flag(), "the search");
    return s.objective(x);
  } catch (const WorkStopped&) {
    s.stopped = true;
    throw nlopt::forced_stop();  // ends optimize() at once
  }
}

}  // namespace

nlopt::result optimize_stoppably(nlopt::opt& opt, std::vector<double>& x, double& minimum,
                                 const SearchObjective& objective) {
  StoppableObjective s{objective};
  opt.set_min_objective(evaluate_stoppably, &s);
  try {
    const nlopt::result code = opt.optimize(x, minimum);
    if (s.stopped) throw WorkStopped("the search: stopped on request");
    return code;
  } catch (const WorkStopped&) {
    throw;
  } catch (...) {
    if (s.stopped) throw WorkStopped("the search: stopped on request");
    throw;
  }
}

}  // namespace rover::study
