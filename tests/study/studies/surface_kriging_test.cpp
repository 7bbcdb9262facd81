// The kriged (f, c_q) surface on known functions: a smooth "RMS" is
// predicted on the grid within its 3-sd band, a log-normally noisy "t_c" gets
// an estimated nugget and a calibrated band; the study keys are checked.
#include "study/studies/surface_kriging.hpp"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "io/json_reader.hpp"
#include "study/design/design.hpp"
#include "study/estimators/splitmix64.hpp"
#include "study/runtime/run_record.hpp"

namespace rover::study {
namespace {

constexpr double kFMin = 1e2, kFMax = 1e5, kCqMin = 0.05, kCqMax = 0.5;
constexpr double kNoiseSd = 0.1;  // of log t_c

double smooth_rms(double f, double c_q) {
  const double u = std::log10(f) - 3.0;
  return 1e-3 * (1.0 + 0.5 * std::sin(1.3 * u) + (c_q - 0.25) * (c_q - 0.25) * 8.0 + 0.2 * u * c_q);
}

double log_t_c(double f, double c_q) { return std::log(0.02) + 0.3 * (std::log10(f) - 2.0) - c_q; }

// A standard normal number from (seed, i) (Box-Muller).
double normal(std::uint64_t seed, std::uint64_t i) {
  const auto u = [&](std::uint64_t k) {
    return (static_cast<double>(splitmix64(seed * 0x9E3779B97F4A7C15ull + k) >> 11) + 0.5) / 9007199254740992.0;
  };
  return std::sqrt(-2.0 * std::log(u(2 * i))) * std::cos(2.0 * M_PI * u(2 * i + 1));
}

SurfaceKrigingSpec spec_of(const std::string& extra_keys) {
  const io::Json json = io::parse_json_text(R"({"surrogate": "gp", "runs": 60, "seed": 7)" + extra_keys + "}", "s.json");
  const io::JsonReader r(json, "s.json");
  return parse_surface_kriging(r, "s.json", kFMin, kFMax, /*f_log=*/true, kCqMin, kCqMax, /*c_q_log=*/false);
}

TEST(SurfaceKriging, PredictsASmoothSurfaceAndANoisyTimeWithinTheirBands) {
  const SurfaceKrigingSpec spec = spec_of("");
  SurfaceKriging k;
  k.x = surface_kriging_design(spec);
  k.rms.resize(k.x.rows());
  k.t_c.resize(k.x.rows());
  k.status.assign(static_cast<std::size_t>(k.x.rows()), run_status::kOk);
  for (Eigen::Index i = 0; i < k.x.rows(); ++i) {
    k.rms(i) = smooth_rms(k.x(i, 0), k.x(i, 1));
    k.t_c(i) = std::exp(log_t_c(k.x(i, 0), k.x(i, 1)) + kNoiseSd * normal(3, static_cast<std::uint64_t>(i)));
  }
  const std::vector<double> f = log_grid(kFMin, kFMax, 12), c_q = linear_grid(kCqMin, kCqMax, 10);
  fit_surface_kriging(spec, f, c_q, k);
  Eigen::MatrixXd rms(12, 10), t_c(12, 10);
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 10; ++j) {
      rms(i, j) = smooth_rms(f[i], c_q[j]);
      t_c(i, j) = std::exp(log_t_c(f[i], c_q[j]) + kNoiseSd * normal(5, static_cast<std::uint64_t>(i * 10 + j)));
    }
  check_surface_kriging(rms, t_c, "test grid", k);
  ASSERT_EQ(k.maps.size(), 2u);
  const SurfaceKrigingMap& r = k.maps[0];
  const SurfaceKrigingMap& t = k.maps[1];
  ASSERT_TRUE(r.fitted && t.fitted);
  std::printf("kriged surface: rms Q2 %.5f, %d of %d within 3 sd; log t_c nugget %.3g (noise sd %.3f, true %.3f), "
              "%d of %d within 3 sd\n",
              r.q2, r.covered_points, r.checked_points, t.model.gp.nugget,
              std::sqrt(t.model.gp.nugget * t.model.gp.process_variance), kNoiseSd, t.covered_points,
              t.checked_points);
  EXPECT_GT(r.q2, 0.999);
  EXPECT_GE(r.coverage, 0.95);
  EXPECT_TRUE(t.log_scale);
  EXPECT_NEAR(std::sqrt(t.model.gp.nugget * t.model.gp.process_variance), kNoiseSd, 0.4 * kNoiseSd);
  EXPECT_GE(t.coverage, 0.95);
  EXPECT_TRUE((t.mean.array() > 0.0).all());
}

TEST(SurfaceKriging, RefusesBadKeysNamingTheField) {
  const auto message = [](const std::string& extra) {
    try {
      spec_of(extra);
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("(nothing thrown)");
  };
  EXPECT_NE(message(R"(, "check": "grids")").find("check"), std::string::npos);
  EXPECT_NE(message(R"(, "gp": {"trend": "quadratic"})").find("trend"), std::string::npos);
  const io::Json few = io::parse_json_text(R"({"surrogate": "gp", "runs": 3})", "s.json");
  EXPECT_THROW(parse_surface_kriging(io::JsonReader(few, "s.json"), "s.json", kFMin, kFMax, true, kCqMin, kCqMax, false),
               io::ConfigError);
  const io::Json pce = io::parse_json_text(R"({"surrogate": "pce", "runs": 60})", "s.json");
  EXPECT_THROW(parse_surface_kriging(io::JsonReader(pce, "s.json"), "s.json", kFMin, kFMax, true, kCqMin, kCqMax, false),
               io::ConfigError);
  const io::Json stray = io::parse_json_text(R"({"runs": 60})", "s.json");
  EXPECT_THROW(parse_surface_kriging(io::JsonReader(stray, "s.json"), "s.json", kFMin, kFMax, true, kCqMin, kCqMax, false),
               io::ConfigError);
}

}  // namespace
}  // namespace rover::study
