// The verdict on a checked calibration fit (calibration_fit_flaw.hpp): why
// its Gauss-Newton intervals cannot be trusted, in words.
#include "study/studies/calibration_fit_flaw.hpp"

#include <string>
#include <utility>

#include "study/studies/calibration_probe.hpp"
#include "study/studies/report_number.hpp"

namespace rover::study {
namespace {

// A fitted value this close to a bound (relative to the bounds' width) is on it.
constexpr double kOnBoundRelative = 1e-6;

// The bounds of a parameter of the Gauss-Newton uncertainty (a fitted one or
// a curve's time offset).
std::pair<double, double> bounds_of(const CheckedFit& c, const std::string& name) {
  for (const FitParameter& f : c.study.fit)
    if (f.name == name) return {f.lower, f.upper};
  return {c.study.offset_min_s, c.study.offset_max_s};
}

// The fitted parameters and time offsets that ended on a bound, or so near
// one that their 95 % interval reaches past it, in words; empty when none
// did. A Gauss-Newton interval there is of a constrained optimum: the bound,
// not the data, may hold the value.
std::string on_a_bound(const CheckedFit& c) {
  std::string text;
  auto check = [&](const std::string& name, double value, double lower, double upper, const std::string& field) {
    const double tolerance = kOnBoundRelative * (upper - lower);
    if (value - lower > tolerance && upper - value > tolerance) return;
    text += (text.empty() ? "" : "; ") + name + " = " + format_number(value, 6) + " is on its bound (widen " + field + ")";
  };
  for (std::size_t k = 0; k < c.study.fit.size(); ++k) {
    const FitParameter& f = c.study.fit[k];
    check(f.name, c.fit.values[k], f.lower, f.upper, "bounds." + f.name);
  }
  for (std::size_t k = 0; k < c.fit.offsets.size() && !c.study.offset_fitted(); ++k)
    check(c.fit.offsets.size() == 1 ? "time_offset" : "time_offset[" + std::to_string(k) + "]", c.fit.offsets[k],
          c.study.offset_min_s, c.study.offset_max_s, "bounds.time_offset");
  if (!text.empty() || !c.gn.ok) return text;
  // Just inside a bound: the 95 % interval reaches past it, so the bound may
  // be what holds the value there.
  const LeastSquaresUncertainty& u = c.gn.uncertainty;
  for (Eigen::Index k = 0; k < u.standard_error.size(); ++k) {
    const std::string& name = c.gn.names[static_cast<std::size_t>(k)];
    const auto [lower, upper] = bounds_of(c, name);
    if (!(u.lower[k] < lower || u.upper[k] > upper)) continue;
    text += (text.empty() ? "" : "; ") + name + "'s 95 % interval [" + format_number(u.lower[k], 6) + ", " +
            format_number(u.upper[k], 6) + "] reaches past its bound " +
            format_number(u.lower[k] < lower ? lower : upper, 6) + " (widen bounds." + name + ")";
  }
  return text;
}

// The parameters the data leave undetermined, in words: a standard error that
// is not finite, a 95 % interval wider than the parameter's bounds (a
// parameter the curves barely depend on, such as a damping when the data end
// before the contact: the profile probe cannot test it, its points lie
// outside the bounds), or a Jacobian of lower rank than the parameters.
// Empty when every parameter is determined.
std::string undetermined_parameters(const CheckedFit& c) {
  const LeastSquaresUncertainty& u = c.gn.uncertainty;
  std::string names;
  for (Eigen::Index k = 0; k < u.standard_error.size(); ++k) {
    const std::string& name = c.gn.names[static_cast<std::size_t>(k)];
    const auto [lower, upper] = bounds_of(c, name);
    if (!std::isfinite(u.standard_error[k]) || !(u.upper[k] - u.lower[k] < upper - lower))
      names += (names.empty() ? "" : ", ") + name;
  }
  if (names.empty() && u.rank >= u.standard_error.size()) return "";
  return "the data do not determine " + (names.empty() ? std::string("every parameter") : names) +
         ": its 95 % interval is wider than its bounds (the Jacobian has rank " + std::to_string(u.rank) + " of " +
         std::to_string(u.standard_error.size()) + ")" + (u.warning.empty() ? "" : "; " + u.warning);
}

}  // namespace

std::string checked_fit_flaw(const CheckedFit& c) {
  if (!c.fit.converged) return "the fit did not converge: " + c.fit.message;
  if (!c.gn.ok) return c.gn.message;
  if (const std::string undetermined = undetermined_parameters(c); !undetermined.empty()) return undetermined;
  if (const std::string bound = on_a_bound(c); !bound.empty()) return bound;
  if (!c.probe.better_values.empty())
    return "a point " + format_number(-c.probe.better_delta_chi2, 3) + " chi-square units below the fit remains after " +
           std::to_string(kMaxProbeRestarts) + " refits from better points: the objective is too rugged for a local fit";
  if (!c.probe.flat.empty()) return describe_flat_parameters(c.probe, c.study);
  return "";
}

}  // namespace rover::study
