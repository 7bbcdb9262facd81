// The verdict on a checked calibration fit (docs/studies.md, calibration):
// why its Gauss-Newton intervals cannot be trusted. Shared by the fit, which
// flags its result NOT VALID, and the posterior, which says what the fit its
// chains start from is flagged for.
#pragma once

#include <string>

#include "study/studies/calibration_checked_fit.hpp"

namespace rover::study {

// Rank 0: why the intervals of a checked fit cannot be trusted (not
// converged, no Gauss-Newton uncertainty, a parameter the data do not
// determine or on its bound, a rugged objective, a flat profile); empty when
// they can be.
std::string checked_fit_flaw(const CheckedFit& checked);

}  // namespace rover::study
