// QoIs on a synthetic trajectory whose answers are known in closed form.
#include "study/model/qoi.hpp"

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace rover::study {
namespace {

// Piecewise-linear z(t) through knots that lie on the 1 ms grid.
double knots_z(double t) {
  const double kt[] = {0.0, 0.18, 0.30, 0.45, 1.0};
  const double kz[] = {0.28, 0.17, 0.21, 0.195, 0.197};
  for (int i = 0; i < 4; ++i)
    if (t <= kt[i + 1]) return kz[i] + (kz[i + 1] - kz[i]) * (t - kt[i]) / (kt[i + 1] - kt[i]);
  return kz[4];
}

Trajectory synthetic() {
  Trajectory tr;
  const int n = 1001;
  tr.q.resize(n, kNumCoordinates);
  tr.q.setZero();
  tr.u.resize(n, kNumCoordinates);
  tr.normal_force_N.resize(n, kNumLegs);
  for (int k = 0; k < n; ++k) {
    const double t = k * 1e-3;
    tr.t.push_back(t);
    tr.B_l_z.push_back(knots_z(t));
    tr.B_r_z.push_back(0.2 + 0.038 * std::exp(-std::pow((t - 0.5) / 0.05, 2)));
    tr.G_z.push_back(0.25 + 0.023 * std::sin(std::numbers::pi * t));
    tr.pitch.push_back(0.1 * std::sin(6.0 * std::numbers::pi * t));
    tr.roll.push_back(-0.05 * t);
    tr.q(k, coord::y) = 0.012 * t;
    tr.q(k, coord::yaw) = -0.01 * t;
    for (int w = 0; w < kNumLegs; ++w) tr.normal_force_N(k, w) = 10.0 + (w == 2 ? 45.0 * std::exp(-std::pow((t - 0.2) / 0.01, 2)) : 0.0);
  }
  return tr;
}

double qoi(const std::string& name, const Trajectory& tr) {
  QoiSpec s;
  s.name = name;
  s.kind = qoi_kind_from_name(name);
  return compute_qoi(s, tr);
}

TEST(Qoi, KnownAnswersOfASyntheticTrajectory) {
  const Trajectory tr = synthetic();
  EXPECT_NEAR(qoi("B_l_z_min", tr), 0.17, 1e-15);
  EXPECT_NEAR(qoi("t_min", tr), 0.18, 1e-12);
  EXPECT_NEAR(qoi("at_rest", tr), 0.197, 1e-15);
  EXPECT_NEAR(qoi("deflection", tr), 0.027, 1e-15);
  EXPECT_NEAR(qoi("rebound_peak", tr), 0.21, 1e-15);
  // |z - 0.197| > 5e-4 until z rises past 0.1965 at t = 0.45 + 0.55 * 1.5 / 2 = 0.8625.
  EXPECT_NEAR(qoi("settling_time", tr), 0.8625, 1e-3);
  EXPECT_NEAR(qoi("max_abs_pitch", tr), 0.1, 1e-4);
  EXPECT_NEAR(qoi("max_abs_roll", tr), 0.05, 1e-15);
  EXPECT_NEAR(qoi("max_wheel_load", tr), 55.0, 1e-12);
  EXPECT_NEAR(qoi("B_r_rise", tr), 0.038, 1e-12);
  EXPECT_NEAR(qoi("G_rise", tr), 0.023, 1e-8);
  EXPECT_NEAR(qoi("lateral_drift", tr), 0.012, 1e-15);
  EXPECT_NEAR(qoi("yaw_drift", tr), -0.01, 1e-15);
}

TEST(Qoi, SettlingBandIsTheStatedOne) {
  const Trajectory tr = synthetic();
  QoiSpec s;
  s.kind = QoiKind::kSettlingTime;
  s.settling_band = 1.5e-3;  // z > 0.1955 from t = 0.45 + 0.55 * 0.5 / 2 = 0.5875
  EXPECT_NEAR(compute_qoi(s, tr), 0.5875, 1e-3);
  s.settling_band = 1.0;  // never outside: the start
  EXPECT_EQ(compute_qoi(s, tr), 0.0);
}

TEST(Qoi, RmsAgainstAShiftedReferenceIsItsOffset) {
  const Trajectory tr = synthetic();
  auto ref = std::make_shared<ReferenceCurve>();
  ref->time_offset_s = 0.05;  // reference clock = simulation clock + 0.05 s
  for (int k = 0; k <= 600; ++k) {
    const double t = 0.05 + 0.002 * k;  // 500 Hz, from the release at 0.05 s
    ref->t.push_back(t);
    ref->value.push_back(knots_z(t - 0.05) + 1e-3);
  }
  QoiSpec s;
  s.kind = QoiKind::kRmsVs;
  s.reference = ref;
  EXPECT_NEAR(compute_qoi(s, tr), 1e-3, 1e-12);
}

TEST(Qoi, AReferenceInMillisecondsIsRefusedByItsShareOfTheRun) {
  // A 0.3 s drop recorded at 20 kHz: in seconds it fits the 0.3 s run; in
  // milliseconds 7 of its 6000 samples lie in the run, 0.1 % of its span.
  std::vector<double> seconds, milliseconds;
  for (int k = 0; k < 6000; ++k) {
    seconds.push_back(k / 20000.0);
    milliseconds.push_back(k / 20.0);
  }
  EXPECT_EQ(reference_span_problem(seconds, 0.0, 0.3), "");
  const std::string p = reference_span_problem(milliseconds, 0.0, 0.3);
  EXPECT_NE(p.find("cover reference times 0 .. 0.3 s: only 0.1 % of its time span"), std::string::npos) << p;
  EXPECT_NE(p.find("t runs to 299.95, milliseconds?"), std::string::npos) << p;
  // Fewer than 3 samples in the run: the sample count is named first.
  EXPECT_NE(reference_span_problem({0.0, 1.0, 2.0}, 0.0, 0.3).find("which hold 1 of its samples"), std::string::npos);
}

TEST(Qoi, NamesAndChannelsRoundTripAndUnknownsListTheValidOnes) {
  for (const std::string& n : qoi_kind_names()) {
    QoiSpec s;
    s.kind = qoi_kind_from_name(n);
    EXPECT_FALSE(qoi_description(s).empty());
  }
  for (const std::string& c : channel_names()) EXPECT_EQ(channel_name(channel_from_name(c)), c);
  try {
    qoi_kind_from_name("B_l_zmin");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("B_l_z_min"), std::string::npos);
  }
  const Trajectory tr = synthetic();
  EXPECT_EQ(channel_values(tr, Channel::kFn3)[200], 55.0);
  EXPECT_EQ(channel_values(tr, Channel::kRoll), tr.roll);
}

}  // namespace
}  // namespace rover::study
