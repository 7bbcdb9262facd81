// An NLopt search that a signal ends at once (docs/reliability.md,
// interrupts): NLopt turns every exception of an objective into a result
// code, so the stop is carried past it here and thrown again as WorkStopped.
#pragma once

#include <functional>
#include <vector>

#include <nlopt.hpp>

namespace rover::study {

using SearchObjective = std::function<double(const std::vector<double>&)>;

// opt.optimize(x, minimum) on `objective` (set here as opt's minimum
// objective). Before each evaluation InterruptGuard::flag() is read, and a
// run in progress ends at its next step: once a signal arrived, the search
// ends and WorkStopped is thrown, whatever NLopt made of it. NLopt's own
// exceptions (roundoff_limited, failure, ...) pass unchanged otherwise.
nlopt::result optimize_stoppably(nlopt::opt& opt, std::vector<double>& x, double& minimum,
                                 const SearchObjective& objective);

}  // namespace rover::study
