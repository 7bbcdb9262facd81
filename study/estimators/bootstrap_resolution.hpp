// Which confidence levels a percentile bootstrap can resolve. Its interval's
// ends are the (1 - c)/2 and (1 + c)/2 quantiles of the B replicates; they
// differ from the replicates' extremes only when at least one replicate is
// expected outside the interval, B (1 - c) >= 1, i.e. B >= 1 / (1 - c). A
// 0.999999 interval from 100 replicates is their minimum and maximum (a 99 %
// interval at best), whatever level it is printed with.
#pragma once

#include <cmath>
#include <string>

#include "core/number_text.hpp"

namespace rover::study {

// The fewest independent units (pick-freeze groups, Morris trajectories) a
// bootstrap resamples. With fewer, most resamples repeat a few units, there
// are few distinct ones (3 of 2 units), and a percentile interval covers far
// less often than its level says: below it an estimator gives no interval.
inline constexpr int kMinBootstrapUnits = 10;

// The fewest replicates that resolve an interval at `confidence` in (0, 1).
inline double min_bootstrap_resamples(double confidence) {
  constexpr double kRounding = 1e-9;  // 1 / (1 - 0.95) is 20 up to rounding
  return std::ceil(1.0 / (1.0 - confidence) - kRounding);
}

// Empty if `resamples` replicates resolve `confidence`; otherwise why not,
// naming both settings by `confidence_field` and `resamples_field`, and the
// highest confidence that `max_resamples`, the most a study may ask for, resolve.
inline std::string bootstrap_resolution_problem(double confidence, const std::string& confidence_field,
                                                double resamples, const std::string& resamples_field,
                                                double max_resamples) {
  const double needed = min_bootstrap_resamples(confidence);
  if (resamples >= needed) return "";
  return confidence_field + " " + number_text(confidence) + " with " + resamples_field + " " +
         number_text(resamples) + ": the interval's ends would be the resamples' extremes; this confidence " +
         "needs at least " + number_text(needed) + " resamples" +
         (needed > max_resamples
              ? ", more than the " + number_text(max_resamples) + " allowed: give a confidence of at most " +
                    number_text(1.0 - 1.0 / max_resamples)
              : ", and " + number_text(resamples) + " resolve a confidence of at most " +
                    number_text(1.0 - 1.0 / resamples));
}

}  // namespace rover::study
