// `rover compare A B`: the metrics of docs/model.md §8 between two curves.
// Measured CSV curves t,z go through io::read_measured_curve's checks; a metric
// that is not finite (a flat reference makes eq. 10 divide by zero) is an
// error naming it, not JSON null; an RMS beyond the span of the reference's
// values (a curve in millimetres) is a warning (core/reference_miss.hpp).
#include <algorithm>
#include <iomanip>
#include <map>
#include <optional>
#include <iostream>
#include <tuple>

#include "core/curve_overlap.hpp"
#include "core/metrics.hpp"
#include "core/reference_miss.hpp"
#include "drivers/command_registry.hpp"
#include "drivers/options.hpp"
#include "io/csv.hpp"
#include "io/json_reader.hpp"
#include "io/trajectory_io.hpp"

namespace rover::cli {
namespace {

struct CompareOptions {
  std::string first, second, column = "B_l_z";
  double rest_time_s = 1.0;      // the paper's at-rest time
  bool rest_time_given = false;  // --rest-time typed (else the default)
  double time_offset_s = 0.0;
};

std::string span_text(const io::Curve& c) {
  return "[" + number_text(c.t.front()) + ", " + number_text(c.t.back()) + "] s";
}

// The one time both curves' at-rest values z_r are read at: the rest time
// when both cover it (to a rounding of their sampling steps). A typed rest
// time outside the times both cover is refused naming them; the default one
// (the paper's 1 s) is replaced, with a warning, by the last time both cover:
// z_r read at each curve's own end would compare two instants of a moving
// curve.
double common_rest_time(double rest_time_s, bool given, const io::Curve& a, const io::Curve& b) {
  const CommonSpan span = common_span(a.t, b.t);
  if (const std::optional<double> t = time_in_span(rest_time_s, span, sample_time_tolerance_s(a.t, b.t))) return *t;
  const std::string where = (given ? "" : "the default ") + ("--rest-time " + number_text(rest_time_s) +
                            " s lies outside the times both curves cover, [" + number_text(span.first_s) + ", " +
                            number_text(span.last_s) + "] s (curve A " + span_text(a) + ", curve B " +
                            span_text(b) + " on A's clock)");
  if (given)
    throw std::invalid_argument(where + ": give a rest time within [" + number_text(span.first_s) + ", " +
                                number_text(span.last_s) + "] s, where both curves' z_r are read at one time");
  std::cerr << "rover compare: warning: " << where << "; z_r of both is read at " << number_text(span.last_s)
            << " s, the last time both cover (give --rest-time to choose another)\n";
  return span.last_s;
}

// Eqs. 10 and 11 divide by the reference's rise from its lowest point to the
// rest time and by its height at the rest time: either being zero leaves that
// error undefined, refused naming curve B and --rest-time.
void check_reference_divisors(const CompareOptions& o, double rest_time_s, const io::Curve& b) {
  const double z_rest = interpolate(b.t, b.y, rest_time_s);
  const double rise = z_rest - *std::min_element(b.y.begin(), b.y.end());
  const std::string reference = "curve B ('" + o.second + "', column " + o.column + ")";
  const std::string rest = "--rest-time " + number_text(rest_time_s) + " s";
  if (!(rise != 0.0))
    throw std::invalid_argument("deflection_error (eq. 10) is undefined: " + reference +
                                ", the reference, rises by 0 m from its lowest point to " + rest +
                                " (eq. 10 divides by that rise); give a rest time after its rebound, or "
                                "a reference that rebounds; nothing printed");
  if (!(z_rest != 0.0))
    throw std::invalid_argument("at_rest_error (eq. 11) is undefined: " + reference + " is at height 0 m at " +
                                rest + " (eq. 11 divides by it); nothing printed");
}

// A curve that misses the reference by more than the span of the
// reference's values is in other units or of another column (a measured
// curve in millimetres): a warning, as for the studies' references.
void warn_if_reference_missed(const CompareOptions& o, double rms, const io::Curve& b) {
  const double span = value_span(b.y);
  if (!every_rms_exceeds_span({rms}, span)) return;
  const std::string unit = o.column.ends_with("_z") ? "m" : "";
  const std::string who = "curve A ('" + o.first + "') misses (RMS " + number_text(rms) + (unit.empty() ? "" : " " + unit) + ")";
  std::cerr << "rover compare: warning: "
            << reference_missed_text(who, "curve B ('" + o.second + "', column " + o.column + ")", span, unit, "column named")
            << "\n";
}

// Each curve has at least kMeasuredCurveMinRows samples, and at least
// kMinCurveShareCompared of its time span, inside the two curves' common time
// interval: an RMS over one common sample, or over the first 0.3 ms of a
// 20 kHz curve in milliseconds against a run in seconds, says nothing.
void check_common_samples(const CompareOptions& o, const io::Curve& a, const io::Curve& b) {
  const double lo = std::max(a.t.front(), b.t.front()), hi = std::min(a.t.back(), b.t.back());
  const std::string interval = "the curves' common time interval [" + number_text(lo) + ", " + number_text(hi) +
                               "] s (A " + span_text(a) + ", B " + span_text(b) + " on A's clock)";
  for (const auto& [name, path, curve] : {std::tuple{"A", &o.first, &a}, std::tuple{"B", &o.second, &b}}) {
    const auto inside = std::count_if(curve->t.begin(), curve->t.end(), [&](double t) { return t >= lo && t <= hi; });
    if (inside < static_cast<std::ptrdiff_t>(io::kMeasuredCurveMinRows))
      throw std::invalid_argument("only " + std::to_string(inside) + " of curve " + name + "'s samples ('" + *path +
                                  "') lie in " + interval + "; an RMS needs at least " +
                                  std::to_string(io::kMeasuredCurveMinRows) +
                                  ": are its times in milliseconds, or --time-offset wrong?");
    if (const std::string p = curve_share_problem(curve->t.front(), curve->t.back(), lo, hi); !p.empty())
      throw std::invalid_argument("curve " + std::string(name) + " ('" + *path + "') beside " + interval + ": " + p +
                                  "; or is --time-offset wrong?");
  }
}

// A measured curve that declares its channel (rover synthesize writes it)
// is compared as that channel only: another --column compares unlike things.
void check_declared_channels(const CompareOptions& o, FlagChecks& checks) {
  for (const auto& [which, path] : {std::pair{"curve A", o.first}, std::pair{"curve B", o.second}})
    if (const std::string declared = io::declared_channel(path); !declared.empty() && declared != o.column)
      checks.add(std::string(which) + " ('" + path + "') declares its z to be " + declared + ", but --column is " +
                 o.column + ": give --column " + declared + ", or a curve of " + o.column);
}

// compare's measures are of heights: RMS and max in metres, eqs. 10-11 of
// a drop's rise to rest. A trajectory's other datasets are refused by name.
void check_height_column(const CompareOptions& o, FlagChecks& checks) {
  static const std::map<std::string, std::string> kNotHeights = {
      {"t", "the time itself"},          {"q", "a matrix of the 23 coordinates"},
      {"u", "a matrix of the 23 speeds"}, {"Fn", "a matrix of the 4 wheels' normal forces"},
      {"pitch", "an angle"},             {"roll", "an angle"},
      {"coordinate_names", "the coordinates' names"}};
  // The columns of a simulated CSV: Fn_1 ... Fn_4, u_<coordinate>, q_<coordinate>.
  const std::string& c = o.column;
  std::string what;
  if (const auto found = kNotHeights.find(c); found != kNotHeights.end()) what = found->second;
  else if (c.size() == 4 && c.starts_with("Fn_") && c[3] >= '1' && c[3] <= '4') what = "a wheel's normal force [N]";
  else if (c.starts_with("u_")) what = "a speed of the coordinate " + c.substr(2);
  else if (c.starts_with("q_") && c != "q_z") what = "the coordinate " + c.substr(2) + " (an angle or a horizontal position)";
  if (!what.empty())
    checks.add("--column " + c + " is " + what + ", not a height: compare measures heights (its RMS in metres, "
               "eqs. 10-11 of a drop's rise to rest); give B_l_z, B_r_z, G_z, q_z or a CSV's height column");
}

int run_compare(const CompareOptions& o) {
  FlagChecks checks;
  check_height_column(o, checks);
  checks.finite("--rest-time", o.rest_time_s);
  checks.finite("--time-offset", o.time_offset_s);
  check_declared_channels(o, checks);
  checks.throw_if_any();
  const io::Curve a = io::read_curve(o.first, o.column);
  io::Curve b = io::read_curve(o.second, o.column);
  for (double& t : b.t) t -= o.time_offset_s;  // B's clock -> A's clock
  if (a.t.back() < b.t.front() || b.t.back() < a.t.front())
    throw std::invalid_argument("curve A " + span_text(a) + " and curve B " + span_text(b) +
                                " (on A's clock, --time-offset " + number_text(o.time_offset_s) +
                                " s) have no common time interval: give the offset of A's t = 0 on B's clock");
  check_common_samples(o, a, b);
  const double rest_time_s = common_rest_time(o.rest_time_s, o.rest_time_given, a, b);
  check_reference_divisors(o, rest_time_s, b);
  io::Json out;
  out["column"] = o.column;
  out["rms_m"] = rms_difference(a.t, a.y, b.t, b.y);
  out["max_abs_difference_m"] = [&] {
    double m = 0.0;
    for (std::size_t i = 0; i < a.t.size(); ++i)
      if (a.t[i] >= b.t.front() && a.t[i] <= b.t.back())
        m = std::max(m, std::abs(interpolate(b.t, b.y, a.t[i]) - a.y[i]));
    return m;
  }();
  // A is the one judged, B the reference (eqs. 10-11).
  out["deflection_error"] = deflection_error(a.t, a.y, b.t, b.y, rest_time_s);
  out["at_rest_error"] = at_rest_error(a.t, a.y, b.t, b.y, rest_time_s);
  out["rest_time_s"] = rest_time_s;
  out["time_offset_s"] = o.time_offset_s;
  require_finite_output(out);
  warn_if_reference_missed(o, out["rms_m"].get<double>(), b);
  std::cout << std::setw(2) << out << "\n";
  return 0;
}

const RegisterCommand compare_command{
    45, "compare", "Compare two curves: RMS, deflection error (eq. 10), at-rest error (eq. 11)",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<CompareOptions>();
      app.footer(
          "A and B are HDF5 trajectories (rover simulate) or CSV files with a header: a 't' column\n"
          "and the compared column (or 'z', as in measured drop data 't,z'). B is the reference:\n"
          "B is interpolated linearly onto A's sample times over the common interval.\n\n"
          "Example:\n"
          "  rover compare results/drop_horizontal.h5 configs/data/drop_horizontal_synthetic.csv \\\n"
          "      --time-offset 0.05 --rest-time 0.9");
      app.add_option("A", o->first, "Curve to judge (.h5 or .csv)")->required()->check(CLI::ExistingFile);
      app.add_option("B", o->second, "Reference curve (.h5 or .csv)")->required()->check(CLI::ExistingFile);
      app.add_option("--column", o->column, "Height dataset or column to compare: B_l_z, B_r_z, G_z, or a CSV's column")->capture_default_str();
      CLI::Option* rest_time =
          app.add_option("--rest-time", o->rest_time_s,
                         "Time of the at-rest value z_r of both curves [s], within the times both cover (the "
                         "default, outside them, gives way to the last time both cover, with a warning)")
              ->capture_default_str();
      app.add_option("--time-offset", o->time_offset_s,
                     "Time of A's t = 0 on B's clock [s] (e.g. the release time in measured data)")
          ->capture_default_str();
      return [o, rest_time] {
        o->rest_time_given = rest_time->count() > 0;
        return run_compare(*o);
      };
    }};

}  // namespace
}  // namespace rover::cli
