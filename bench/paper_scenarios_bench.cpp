// An integrator on the five paper scenarios (docs/model.md §7 and §9):
// for the two drops and the obstacle runs at 0.34, 1 and 2 m/s, the
// Rosenbrock-W integrator at its default settings (or the method of
// --method) against Dormand-Prince at a tight tolerance (rtol 1e-10, atol
// 1e-13): wall time (best of three; one run with dopri5; --repeats N),
// accepted and rejected steps, right-hand sides, and the RMS and largest difference of
// B_l z and B_r z over every sample. This is the accuracy the studies rely on
// when they use the stiff integrator (target: within 0.05 mm RMS), and the
// cost of one run they pay.
//
// The references take minutes; they are kept in a cache directory (default
// /tmp/rover_reference_cache; --cache DIR) keyed by scenario, so a second
// run of the table costs seconds. Run on a quiet core:
//   taskset -c 0 build/bench/paper_scenarios_bench [--cache DIR] [--only NAME] [--rtol R] [--atol A]
//       [--slip S] [--method NAME | --dopri5] [--repeats N] [--reference-rtol R] [--lift METRES]
//       [--trace FILE]
// (--rtol and --atol replace the method's default tolerances, --slip its
// slip_tolerance (rosenbrock, rodas4); --method runs
// any integrator by name (rosenbrock, rodas4, dopri5) at its defaults or the
// tolerances given; --dopri5 runs Dormand-Prince at the scenario's own
// tolerances, or those given, to show how far an explicit run
// at practical tolerances is from the reference; --lift starts the run that
// higher, to show how far a tiny change of the initial state moves it;
// --trace writes t, both runs' B_l z and B_r z as CSV, for --only's scenario).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "core/coordinates.hpp"
#include "core/simulate.hpp"
#include "io/scenario_config.hpp"

namespace {

using namespace rover;

// The reference: Dormand-Prince at rtol 1e-10 (--reference-rtol R for
// another; atol is always rtol / 1000), converged to well below 1e-6 mm on
// the drops (tests/core/integrator_dopri5_test.cpp).
constexpr double kReferenceRelativeTolerance = 1e-10, kReferenceAtolPerRtol = 1e-3;

struct Curves {
  std::vector<double> B_l_z, B_r_z;
};

// The reference curves of one scenario, from the cache or computed now.
Curves reference_curves(const io::ScenarioSetup& setup, const std::string& name,
                        const std::filesystem::path& cache_dir, double reference_rtol) {
  char key[64];
  std::snprintf(key, sizeof key, "_dopri5_rtol%.0e.bin", reference_rtol);
  const std::filesystem::path file = cache_dir / (name + key);
  Curves c;
  if (std::ifstream in(file, std::ios::binary); in) {
    std::size_t n = 0;
    in.read(reinterpret_cast<char*>(&n), sizeof n);
    c.B_l_z.resize(n);
    c.B_r_z.resize(n);
    in.read(reinterpret_cast<char*>(c.B_l_z.data()), static_cast<std::streamsize>(n * sizeof(double)));
    in.read(reinterpret_cast<char*>(c.B_r_z.data()), static_cast<std::streamsize>(n * sizeof(double)));
    if (in) return c;
  }
  Scenario tight = setup.scenario;
  tight.integrator = default_integrator_settings(IntegratorMethod::kDormandPrince45);
  tight.integrator.relative_tolerance = reference_rtol;
  tight.integrator.absolute_tolerance = kReferenceAtolPerRtol * reference_rtol;
  tight.wall_time_budget_s = 3600.0;
  std::printf("  (computing the dopri5 reference of %s ...)\n", name.c_str());
  std::fflush(stdout);
  const Trajectory ref = simulate(setup.model, tight, setup.inputs);
  if (!ref.ok()) {
    std::fprintf(stderr, "reference of %s failed: %s\n", name.c_str(), ref.message.c_str());
    std::exit(1);
  }
  c.B_l_z = ref.B_l_z;
  c.B_r_z = ref.B_r_z;
  std::filesystem::create_directories(cache_dir);
  std::ofstream out(file, std::ios::binary);
  const std::size_t n = c.B_l_z.size();
  out.write(reinterpret_cast<const char*>(&n), sizeof n);
  out.write(reinterpret_cast<const char*>(c.B_l_z.data()), static_cast<std::streamsize>(n * sizeof(double)));
  out.write(reinterpret_cast<const char*>(c.B_r_z.data()), static_cast<std::streamsize>(n * sizeof(double)));
  return c;
}

struct Difference {
  double rms_mm = NAN, max_mm = NAN;
};

Difference difference_mm(const std::vector<double>& a, const std::vector<double>& b) {
  Difference d;
  if (a.size() != b.size() || a.empty()) return d;
  double sum = 0.0, largest = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double e = std::abs(a[i] - b[i]);
    sum += e * e;
    largest = std::max(largest, e);
  }
  d.rms_mm = 1e3 * std::sqrt(sum / static_cast<double>(a.size()));
  d.max_mm = 1e3 * largest;
  return d;
}

// A positive finite number, or exit with a message naming the flag.
double positive_number(const char* flag, const char* text) {
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text || *end != '\0' || !(value > 0.0) || !std::isfinite(value)) {
    std::fprintf(stderr, "%s: expected a positive number, got '%s'\n", flag, text);
    std::exit(2);
  }
  return value;
}

// t [s], the run's and the reference's B_l z and B_r z [m], one row a sample.
// Written to FILE.part and renamed, so that FILE is whole or absent.
void write_trace(const std::string& file, double output_rate_hz, const Trajectory& run, const Curves& ref) {
  const std::string part = file + ".part";
  {
    std::ofstream out(part);
    out.precision(12);
    out << "t_s,B_l_z_m,B_l_z_reference_m,B_r_z_m,B_r_z_reference_m\n";
    const std::size_t n = std::min(run.B_l_z.size(), ref.B_l_z.size());
    for (std::size_t k = 0; k < n; ++k)
      out << static_cast<double>(k) / output_rate_hz << ',' << run.B_l_z[k] << ',' << ref.B_l_z[k] << ','
          << run.B_r_z[k] << ',' << ref.B_r_z[k] << '\n';
    out.flush();
    if (out) {
      std::error_code error;
      std::filesystem::rename(part, file, error);
      if (!error) return;
    }
  }
  std::filesystem::remove(part);
  std::fprintf(stderr, "--trace: could not write %s\n", file.c_str());
  std::exit(1);
}

// Stops at once, before minutes of reference runs, if `file` cannot be written.
void check_writable(const std::string& file) {
  const std::string part = file + ".part";
  const bool ok = static_cast<bool>(std::ofstream(part));
  std::filesystem::remove(part);
  if (!ok) {
    std::fprintf(stderr, "--trace: cannot write %s (does its directory exist?)\n", file.c_str());
    std::exit(2);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path cache_dir = "/tmp/rover_reference_cache";
  std::string only;
  IntegratorSettings stiff = default_integrator_settings(IntegratorMethod::kRosenbrockW);
  bool dopri5 = false, tolerances_given = false;
  int repeats = 0;  // 0: three, one for dopri5
  double reference_rtol = kReferenceRelativeTolerance;
  double lift_m = 0.0;
  double slip_tolerance = 0.0;  // 0: the method's default
  std::string trace;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--cache") && i + 1 < argc) {
      cache_dir = argv[++i];
    } else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) {
      only = argv[++i];
    } else if (!std::strcmp(argv[i], "--rtol") && i + 1 < argc) {
      stiff.relative_tolerance = positive_number("--rtol", argv[i + 1]);
      tolerances_given = true;
      ++i;
    } else if (!std::strcmp(argv[i], "--atol") && i + 1 < argc) {
      stiff.absolute_tolerance = positive_number("--atol", argv[i + 1]);
      tolerances_given = true;
      ++i;
    } else if (!std::strcmp(argv[i], "--slip") && i + 1 < argc) {
      slip_tolerance = positive_number("--slip", argv[++i]);
    } else if (!std::strcmp(argv[i], "--dopri5")) {
      dopri5 = true;
    } else if (!std::strcmp(argv[i], "--method") && i + 1 < argc) {
      try {
        const IntegratorMethod method = integrator_from_name(argv[++i]);
        if (method == IntegratorMethod::kDormandPrince45) {
          dopri5 = true;
        } else {
          const IntegratorSettings defaults = default_integrator_settings(method);
          stiff.method = method;
          if (!tolerances_given) stiff = defaults;
        }
      } catch (const std::invalid_argument& e) {
        std::fprintf(stderr, "--method: %s\n", e.what());
        return 2;
      }
    } else if (!std::strcmp(argv[i], "--reference-rtol") && i + 1 < argc) {
      reference_rtol = positive_number("--reference-rtol", argv[++i]);
    } else if (!std::strcmp(argv[i], "--repeats") && i + 1 < argc) {
      repeats = static_cast<int>(positive_number("--repeats", argv[++i]));
    } else if (!std::strcmp(argv[i], "--lift") && i + 1 < argc) {
      lift_m = positive_number("--lift", argv[++i]);
    } else if (!std::strcmp(argv[i], "--trace") && i + 1 < argc) {
      trace = argv[++i];
    } else {
      std::fprintf(stderr, "usage: %s [--cache DIR] [--only SCENARIO] [--rtol R] [--atol A] [--slip S] "
                           "[--method NAME | --dopri5] "
                           "[--repeats N] [--reference-rtol R] [--lift METRES] "
                           "[--trace FILE]\n", argv[0]);
      return 2;
    }
  }
  if (slip_tolerance > 0.0) stiff.slip_tolerance = slip_tolerance;
  const char* const names[] = {"drop_horizontal", "drop_skewed", "obstacle_v034", "obstacle_v1", "obstacle_v2"};
  if (!only.empty() && std::find(std::begin(names), std::end(names), only) == std::end(names)) {
    std::fprintf(stderr, "--only: unknown scenario '%s' (drop_horizontal, drop_skewed, obstacle_v034, "
                         "obstacle_v1, obstacle_v2)\n", only.c_str());
    return 2;
  }
  if (!trace.empty() && only.empty()) {
    std::fprintf(stderr, "--trace needs --only SCENARIO\n");
    return 2;
  }
  if (!trace.empty()) check_writable(trace);
  if (dopri5 && !tolerances_given)
    std::printf("dopri5 (each scenario's own tolerances)");
  else
    std::printf("%s (rtol %.0e, atol %.0e)", dopri5 ? "dopri5" : integrator_name(stiff.method),
                stiff.relative_tolerance, stiff.absolute_tolerance);
  if (!dopri5 && slip_tolerance > 0.0) std::printf(", slip_tol %g,", stiff.slip_tolerance);
  if (lift_m > 0.0) std::printf(", started %g m higher,", lift_m);
  std::printf(" against dopri5 (rtol %.0e, atol %.0e)\n", reference_rtol, kReferenceAtolPerRtol * reference_rtol);
  std::printf("%-16s %9s %7s %7s %7s | %-19s | %-19s\n", "scenario", "wall [s]", "steps", "reject", "rhs",
              "B_l z RMS/max mm", "B_r z RMS/max mm");
  double total_wall_s = 0.0;
  for (const char* name : names) {
    if (!only.empty() && only != name) continue;
    const io::ScenarioSetup setup =
        io::load_scenario(std::string(ROVER_SOURCE_DIR) + "/configs/scenarios/" + name + ".json");
    const Curves ref = reference_curves(setup, name, cache_dir, reference_rtol);
    Scenario run = setup.scenario;
    if (!dopri5) {
      run.integrator = stiff;
    } else if (tolerances_given) {
      run.integrator = default_integrator_settings(IntegratorMethod::kDormandPrince45);
      run.integrator.relative_tolerance = stiff.relative_tolerance;
      run.integrator.absolute_tolerance = stiff.absolute_tolerance;
    } else {
      run.integrator.method = IntegratorMethod::kDormandPrince45;
    }
    run.initial_q[coord::z] += lift_m;
    Trajectory best = simulate(setup.model, run, setup.inputs);
    const int runs = repeats > 0 ? repeats : (dopri5 ? 1 : 3);  // dopri5: one run, slow enough to time
    for (int repeat = 1; repeat < runs; ++repeat) {
      Trajectory again = simulate(setup.model, run, setup.inputs);
      if (again.wall_time_s < best.wall_time_s) best = std::move(again);
    }
    if (!best.ok()) std::printf("%-16s failed: %s\n", name, best.message.c_str());
    const Difference l = difference_mm(best.B_l_z, ref.B_l_z), r = difference_mm(best.B_r_z, ref.B_r_z);
    std::printf("%-16s %9.4f %7ld %7ld %7ld | %8.2e / %8.2e | %8.2e / %8.2e\n", name, best.wall_time_s, best.steps,
                best.rejected_steps, best.rhs_evaluations, l.rms_mm, l.max_mm, r.rms_mm, r.max_mm);
    std::fflush(stdout);
    if (!trace.empty()) write_trace(trace, run.output_rate_hz, best, ref);
    total_wall_s += best.wall_time_s;
  }
  std::printf("total wall %.4f s\n", total_wall_s);
  return 0;
}
