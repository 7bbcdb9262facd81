// The cross-validation of a crowded polynomial chaos selection
// (study/surrogate/cross_validation.hpp) as attributes of a result or saved
// model: its folds (0: not done), its Q^2 when done, why not otherwise.
// docs/results_format.md lists them.
#pragma once

#include <string>

#include "io/hdf5_file.hpp"
#include "study/surrogate/cross_validation.hpp"

namespace rover::study {

inline constexpr const char* kReselectedFoldsAttribute = "reselected_cv_folds";
inline constexpr const char* kReselectedQ2Attribute = "reselected_cv_q2";
inline constexpr const char* kReselectedWhyNotAttribute = "reselected_cv_not_done";

// Writes nothing when the selection was not crowded (folds 0, no why_not).
inline void write_reselected_cross_validation(io::Hdf5Writer& h5, const std::string& object,
                                              const CrossValidation& cv) {
  if (cv.folds == 0 && cv.why_not.empty()) return;
  h5.attribute(object, kReselectedFoldsAttribute, static_cast<long long>(cv.folds));
  if (cv.folds > 0) h5.attribute(object, kReselectedQ2Attribute, cv.q2);
  else h5.attribute(object, kReselectedWhyNotAttribute, cv.why_not);
}

}  // namespace rover::study
