// Wheel-terrain contact (core/contact.cpp; docs/model.md §6): the geometry
// of the deepest rim point against analytic results on flat and planar
// terrain, several contact regions at the foot of a ramp (and their count
// without locating them), the slope normal,
// the mean-slope normal at a convex edge on a grid line (taken once the
// tangent point reaches it), a contact point that moves smoothly with the
// wheel, and the forces: never
// pulling (and the same without the friction), friction against the slip, and
// generalized forces consistent with the virtual power of the contact forces
// and with finite differences.
#include "core/contact.hpp"

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/equations_of_motion.hpp"
#include "core/friction.hpp"
#include "core/obstacle.hpp"
#include "model_fixtures.hpp"

namespace rover {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRadius = 0.085;
const double kRamp = 20.0 * kPi / 180.0;

Mat3 rot(const Vec3& axis, double angle) { return Eigen::AngleAxisd(angle, axis).toRotationMatrix(); }

// Spin axis of a wheel steered by `steer` on a chassis with yaw, pitch, roll
// (all joints at 0): R_WC Rz(steer) e_y, R_WC = Rz Ry Rx (docs/model.md sections 1, 3).
Vec3 spin_axis(double yaw, double pitch, double roll, double steer) {
  return rot(Vec3::UnitZ(), yaw) * rot(Vec3::UnitY(), pitch) * rot(Vec3::UnitX(), roll) *
         rot(Vec3::UnitZ(), steer) * Vec3::UnitY();
}

// The rim point farthest along -direction: the deepest point against a plane
// with upward normal `direction` (a circle's support point).
Vec3 support_point(const Vec3& centre, const Vec3& spin, double radius, const Vec3& direction) {
  const Vec3 in_plane = direction - direction.dot(spin) * spin;
  return centre - radius * in_plane.normalized();
}

// Lowest z of the rim by brute force (1e6 samples: error < R (pi/1e6)^2 / 2 = 4e-13 m).
double lowest_rim_z_sampled(const Vec3& centre, const Vec3& spin, double radius) {
  const Vec3 e1 = spin.unitOrthogonal(), e2 = spin.cross(e1);
  double lowest = centre.z();
  const int n = 1000000;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * kPi * i / n;
    lowest = std::min(lowest, centre.z() + radius * (std::cos(a) * e1.z() + std::sin(a) * e2.z()));
  }
  return lowest;
}

void expect_on_rim(const ContactPoint& c, const Vec3& centre, const Vec3& spin, double radius) {
  EXPECT_NEAR((c.point_m - centre).norm(), radius, 1e-12);
  EXPECT_NEAR((c.point_m - centre).dot(spin), 0.0, 1e-12);
}

const Terrain& obstacle_terrain() {
  static const Terrain terrain = Terrain::from_grid(trapezoid_obstacle_grid(TrapezoidObstacle{}));
  return terrain;
}

// ---------------------------------------------------------------- geometry

TEST(Contact, FlatGroundPenetrationIsExactForATiltedSteeredPitchedWheel) {
  const Terrain ground = Terrain::flat(0.02);
  struct Pose {
    double yaw, pitch, roll, steer;
  };
  for (const Pose& pose : {Pose{0, 0, 0, 0}, Pose{0.3, 0.2, -0.15, 0.7}, Pose{-1.0, -0.35, 0.4, -1.2},
                           Pose{2.0, 0.1, 0.6, 1.5}}) {
    const Vec3 spin = spin_axis(pose.yaw, pose.pitch, pose.roll, pose.steer);
    // Lowest rim point: R sqrt(1 - s_z^2) below the centre.
    const double drop = kRadius * std::sqrt(1.0 - spin.z() * spin.z());
    ASSERT_NEAR(lowest_rim_z_sampled(Vec3::Zero(), spin, kRadius), -drop, 1e-12);
    const Vec3 centre(0.4, -1.3, 0.02 + drop - 0.0031);  // 3.1 mm into the ground
    const WheelContacts w = find_wheel_contacts(ground, centre, spin, kRadius);
    ASSERT_EQ(w.count, 1);
    const ContactPoint& c = w.points[0];
    EXPECT_NEAR(c.penetration_m, 0.0031, 1e-12);
    EXPECT_NEAR(c.depth_m, 0.0031, 1e-12);
    EXPECT_EQ(c.normal, Vec3::UnitZ());
    EXPECT_NEAR(c.point_m.z(), 0.02 - 0.0031, 1e-12);
    EXPECT_LT((c.point_m - support_point(centre, spin, kRadius, Vec3::UnitZ())).norm(), 1e-12);
    expect_on_rim(c, centre, spin, kRadius);

    // Just above the ground: no contact.
    const Vec3 lifted = centre + Vec3(0, 0, 0.0031 + 1e-9);
    EXPECT_EQ(find_wheel_contacts(ground, lifted, spin, kRadius).count, 0);
  }
}

TEST(Contact, ModelWheelsUseTheirSpinAxis) {
  // Through the kinematic tree: chassis yawed, pitched, rolled, wheels steered.
  const RoverModel model = make_rover_model(default_rover_parameters());
  Coordinates q = Coordinates::Zero();
  q[coord::yaw] = 0.4;
  q[coord::pitch] = 0.12;
  q[coord::roll] = -0.08;
  const double steer[4] = {0.5, -0.3, 1.1, -0.9};
  for (int leg = 0; leg < kNumLegs; ++leg) q[coord::steer(leg)] = steer[leg];
  q[coord::z] = 0.22;
  const TreeKinematics kin = forward_kinematics(model.tree, q, Coordinates::Zero());
  const auto contacts = wheel_contacts(model, kin);
  int touching = 0;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const Vec3 spin = spin_axis(q[coord::yaw], q[coord::pitch], q[coord::roll], steer[leg]);
    const Vec3 centre = kin.nodes[node::wheel(leg)].origin;
    const double penetration = -(centre.z() - kRadius * std::sqrt(1.0 - spin.z() * spin.z()));
    if (penetration > 0.0) {
      ASSERT_EQ(contacts[leg].count, 1) << "leg " << leg;
      EXPECT_NEAR(contacts[leg].points[0].penetration_m, penetration, 1e-12) << "leg " << leg;
      expect_on_rim(contacts[leg].points[0], centre, spin, kRadius);
      ++touching;
    } else {
      EXPECT_EQ(contacts[leg].count, 0) << "leg " << leg;
    }
  }
  EXPECT_GE(touching, 2);
  EXPECT_LE(touching, 3);  // the pose makes some, not all, wheels touch
}

TEST(Contact, TiltedPlaneGridMatchesThePlane) {
  // h = c + a x + b y sampled on a grid: bilinear interpolation is the plane.
  const double a = 0.25, b = -0.15, c0 = 0.01;
  const Terrain plane = Terrain::from_grid(
      testing::sampled_grid(-0.5, -0.6, 0.013, 0.017, 90, 80, [&](double x, double y) { return c0 + a * x + b * y; }));
  const Vec3 m(-a, -b, 1.0);  // upward normal, unnormalised
  const Vec3 n = m.normalized();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(-0.6, 0.6), place(-0.2, 0.2);
  for (int trial = 0; trial < 20; ++trial) {
    const Vec3 spin = spin_axis(angle(rng), angle(rng), angle(rng), 2.0 * angle(rng));
    Vec3 centre(place(rng), place(rng), 0.0);
    // Place the centre so the deepest rim point is 3 mm (vertically) below the plane.
    const Vec3 lowest = support_point(centre, spin, kRadius, n);
    centre.z() = c0 + a * lowest.x() + b * lowest.y() - lowest.z() - 0.003;
    // Analytic result at this centre.
    const Vec3 deepest = support_point(centre, spin, kRadius, n);
    const double depth = c0 + a * deepest.x() + b * deepest.y() - deepest.z();
    const WheelContacts w = find_wheel_contacts(plane, centre, spin, kRadius);
    ASSERT_EQ(w.count, 1) << "trial " << trial;
    const ContactPoint& cp = w.points[0];
    EXPECT_NEAR(cp.depth_m, depth, 1e-9) << "trial " << trial;
    EXPECT_NEAR(cp.penetration_m, depth * n.z(), 1e-9) << "trial " << trial;
    EXPECT_LT((cp.normal - n).norm(), 1e-12) << "trial " << trial;
    // Brent's maximiser, to ~sqrt(eps) of the rim angle, refined on the
    // depth's slope along the rim to round-off.
    EXPECT_LT((cp.point_m - deepest).norm(), 1e-12) << "trial " << trial;
    expect_on_rim(cp, centre, spin, kRadius);
  }
}

TEST(Contact, RampNormalFollowsTheSlope) {
  const Terrain& terrain = obstacle_terrain();
  const Vec3 n(-std::sin(kRamp), 0.0, std::cos(kRamp));
  for (double steer : {0.0, 0.5, -0.3}) {
    const Vec3 spin = rot(Vec3::UnitZ(), steer) * Vec3::UnitY();
    const double x_c = 1.50, y_c = -0.2215, penetration = 0.002;
    // Centre at perpendicular distance (R_eff - penetration) from the ramp plane,
    // where R_eff is how far the rim reaches along -n.
    const double reach = kRadius * (n - n.dot(spin) * spin).norm();
    const double z_c = (reach - penetration) / std::cos(kRamp) + (x_c - 1.36) * std::tan(kRamp);
    const Vec3 centre(x_c, y_c, z_c);
    const WheelContacts w = find_wheel_contacts(terrain, centre, spin, kRadius);
    ASSERT_EQ(w.count, 1) << "steer " << steer;
    const ContactPoint& c = w.points[0];
    EXPECT_LT((c.normal - n).norm(), 1e-8) << "steer " << steer << ": " << c.normal.transpose();
    EXPECT_NEAR(c.penetration_m, penetration, 1e-9) << "steer " << steer;
    EXPECT_NEAR(c.depth_m, penetration / std::cos(kRamp), 1e-9) << "steer " << steer;
    EXPECT_LT((c.point_m - support_point(centre, spin, kRadius, n)).norm(), 1e-7);
    expect_on_rim(c, centre, spin, kRadius);
  }
}

TEST(Contact, ContactPointOnTheRampMovesSmoothlyWithTheWheel) {
  // The wheel slides up the ramp by 1e-7 m at a time: its deepest point moves
  // along a straight line, so its second differences are round-off, not the
  // ~1e-9 m by which Brent's method alone would scatter it (a noise in the
  // contact force's moment that holds an explicit integrator to tiny steps).
  const Terrain& terrain = obstacle_terrain();
  const Vec3 spin = rot(Vec3::UnitZ(), 0.2) * Vec3::UnitY();
  const Vec3 n(-std::sin(kRamp), 0.0, std::cos(kRamp)), along(std::cos(kRamp), 0.0, std::sin(kRamp));
  const double reach = kRadius * (n - n.dot(spin) * spin).norm(), penetration = 0.002, x_c = 1.5;
  const Vec3 start(x_c, -0.2215, (reach - penetration) / std::cos(kRamp) + (x_c - 1.36) * std::tan(kRamp));
  std::vector<Vec3> points;
  for (int k = 0; k < 12; ++k) {
    const WheelContacts w = find_wheel_contacts(terrain, start + (1e-7 * k) * along, spin, kRadius);
    ASSERT_EQ(w.count, 1) << "k " << k;
    points.push_back(w.points[0].point_m);
  }
  for (std::size_t k = 1; k + 1 < points.size(); ++k)
    EXPECT_LT((points[k + 1] - 2.0 * points[k] + points[k - 1]).norm(), 1e-13) << "k " << k;
}

TEST(Contact, WheelAtTheFootOfTheRampHasTwoRegions) {
  // 0.5 mm into the flat ground and, in front, into the 20 deg ramp; the rim
  // is above the ground at the foot, so these are two separate regions.
  const Terrain& terrain = obstacle_terrain();
  const double ground_depth = 0.0005, x_c = 1.36 - 0.012;
  const Vec3 centre(x_c, -0.2215, kRadius - ground_depth);
  const Vec3 spin = Vec3::UnitY();
  ASSERT_GT(centre.z() - std::sqrt(kRadius * kRadius - 0.012 * 0.012), 0.0) << "rim above the foot";
  const Vec3 n_ramp(-std::sin(kRamp), 0.0, std::cos(kRamp));
  const double ramp_distance = (1.36 - x_c) * std::sin(kRamp) + centre.z() * std::cos(kRamp);
  ASSERT_LT(ramp_distance, kRadius);

  const WheelContacts w = find_wheel_contacts(terrain, centre, spin, kRadius);
  ASSERT_EQ(w.count, 2);
  const ContactPoint& ground = w.points[0].normal.z() > w.points[1].normal.z() ? w.points[0] : w.points[1];
  const ContactPoint& ramp = &ground == &w.points[0] ? w.points[1] : w.points[0];
  EXPECT_LT((ground.normal - Vec3::UnitZ()).norm(), 1e-12);
  EXPECT_NEAR(ground.penetration_m, ground_depth, 1e-9);
  EXPECT_NEAR(ground.point_m.x(), x_c, 1e-6);
  EXPECT_LT((ramp.normal - n_ramp).norm(), 1e-8);
  EXPECT_NEAR(ramp.penetration_m, kRadius - ramp_distance, 1e-9);
  EXPECT_LT((ramp.point_m - (centre - kRadius * n_ramp)).norm(), 1e-7);
  for (const ContactPoint& c : {ground, ramp}) expect_on_rim(c, centre, spin, kRadius);
}

TEST(Contact, RegionCountIsThatOfTheFoundContacts) {
  // Wheels swept over the whole trapezoid (foot, ramps, convex edges, top)
  // at depths from clear to 20 mm, tilted and steered, and on flat ground:
  // the count alone is the count of the regions find_wheel_contacts()
  // locates, and the sweep meets none, one and two regions.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> along(1.30, 2.30), depth(-0.005, 0.020), tilt(-0.3, 0.3);
  const Terrain flat_ground = Terrain::flat();
  int seen[3] = {0, 0, 0};
  for (int trial = 0; trial < 4000; ++trial) {
    const bool flat = trial % 8 == 0;
    const Terrain& terrain = flat ? flat_ground : obstacle_terrain();
    const double x = along(rng);
    const Vec3 spin = (Eigen::AngleAxisd(tilt(rng), Vec3::UnitZ()) * Eigen::AngleAxisd(tilt(rng), Vec3::UnitX()) *
                       Vec3::UnitY()).normalized();
    const double ground = flat ? 0.0 : terrain.height(x, -0.2215);
    const Vec3 centre(x, -0.2215, ground + kRadius - depth(rng));
    const WheelContacts found = find_wheel_contacts(terrain, centre, spin, kRadius);
    ASSERT_EQ(count_wheel_contact_regions(terrain, centre, spin, kRadius), found.count)
        << "x = " << x << ", centre z = " << centre.z() << (flat ? " (flat)" : "");
    ++seen[std::min(found.count, 2)];
  }
  EXPECT_GT(seen[0], 0);
  EXPECT_GT(seen[1], 0);
  EXPECT_GT(seen[2], 0);
}

TEST(Contact, ConvexEdgeOnAGridLineGivesTheMeanSlopeNormal) {
  // A ridge along y on the grid line x0: slope +0.3 before it, -0.1 after.
  // For a wheel centred just before x0 the deepest rim point is the kink
  // itself (neither plane's own optimum lies on its side), so the contact
  // point must sit on the grid line and take the mean-slope normal.
  const double x0 = 0.5, top = 0.05, up = 0.3, down = -0.1;
  const Terrain ridge = Terrain::from_grid(testing::sampled_grid(0.0, -0.5, 0.01, 0.05, 101, 21, [&](double x, double) {
    return x <= x0 ? top + up * (x - x0) : top + down * (x - x0);
  }));
  ASSERT_DOUBLE_EQ(ridge.height(x0, 0.0), top);
  const Vec3 spin = Vec3::UnitY();
  for (double offset : {-0.005, -0.012, 0.004}) {
    const double x_c = x0 + offset, penetration_at_kink = 0.002;
    const double z_c = top - penetration_at_kink + std::sqrt(kRadius * kRadius - offset * offset);
    const Vec3 centre(x_c, 0.013, z_c);
    const WheelContacts w = find_wheel_contacts(ridge, centre, spin, kRadius);
    ASSERT_EQ(w.count, 1) << "offset " << offset;
    const ContactPoint& c = w.points[0];
    // On the line itself (snapped), not only within the mean-slope tolerance
    // of it where Brent's method stops (~5e-10 m, 1e-10 m short in depth).
    EXPECT_NEAR(c.point_m.x(), x0, 1e-12) << "offset " << offset;
    const Vec3 mean_normal = Vec3(-0.5 * (up + down), 0.0, 1.0).normalized();
    EXPECT_LT((c.normal - mean_normal).norm(), 1e-12) << "offset " << offset << ": " << c.normal.transpose();
    EXPECT_NEAR(c.depth_m, penetration_at_kink, 1e-12) << "offset " << offset;
    EXPECT_NEAR(c.penetration_m, penetration_at_kink * mean_normal.z(), 1e-12);
    expect_on_rim(c, centre, spin, kRadius);
  }
}

// ---------------------------------------------------------------- forces

// The default model on `terrain` with every wheel `penetration` into flat
// ground (chassis level, joints at 0) and speeds u.
struct ForcesAt {
  RoverModel model;
  TreeKinematics kin;
  std::array<WheelContacts, kNumLegs> contacts;
};
ForcesAt forces_at(const Coordinates& q, const Coordinates& u, Terrain terrain = Terrain::flat()) {
  ForcesAt f{make_rover_model(default_rover_parameters(), std::move(terrain)), {}, {}};
  f.kin = forward_kinematics(f.model.tree, q, u);
  f.contacts = wheel_contacts(f.model, f.kin);
  return f;
}
constexpr double kBottomBelowG = 0.2285;  // docs/model.md §3

TEST(Contact, TangentPointReachingAConvexEdgeSwitchesToTheEdgeOnce) {
  // The ridge of the test above; a steered, tilted wheel slides up its +0.3
  // face until its tangent point on the face passes the edge. The contact
  // turns from the face's normal to the edge's mean normal once, where the
  // tangent point reaches the edge, not back and forth at round-off while the
  // two depths agree to 1e-15 m (a jump that would stall any integrator):
  // swept in steps of 1e-12 m across the switch.
  const double x0 = 0.5, top = 0.05, up = 0.3, down = -0.1, penetration = 0.002;
  const Terrain ridge = Terrain::from_grid(testing::sampled_grid(0.0, -0.5, 0.01, 0.05, 101, 21, [&](double x, double) {
    return x <= x0 ? top + up * (x - x0) : top + down * (x - x0);
  }));
  const Vec3 spin = spin_axis(0.0, 0.05, 0.1, 0.3);
  const Vec3 face_normal = Vec3(-up, 0.0, 1.0).normalized();
  const Vec3 offset = support_point(Vec3::Zero(), spin, kRadius, face_normal);  // tangent point - centre
  auto normal_at = [&](double tangent_x) {
    const Vec3 tangent(tangent_x, 0.013, top + up * (tangent_x - x0) - penetration);
    const WheelContacts w = find_wheel_contacts(ridge, tangent - offset, spin, kRadius);
    EXPECT_EQ(w.count, 1) << "tangent point at x " << tangent_x;
    return w.points[0].normal;
  };
  auto switches = [&](double from, double step, int n, double* last_switch) {
    int count = 0;
    Vec3 previous = normal_at(from);
    for (int k = 1; k <= n; ++k) {
      const Vec3 normal = normal_at(from + step * k);
      if ((normal - previous).norm() > 1e-6) {
        ++count;
        *last_switch = from + step * k;
      }
      previous = normal;
    }
    return count;
  };
  EXPECT_LT((normal_at(x0 - 1e-7) - face_normal).norm(), 1e-12);
  double at = 0.0;
  ASSERT_EQ(switches(x0 - 1e-7, 1e-9, 200, &at), 1);
  EXPECT_NEAR(at, x0, 3e-8);
  EXPECT_EQ(switches(at - 2e-10, 1e-12, 400, &at), 1);
  EXPECT_LT((normal_at(x0 + 1e-7) - Vec3(-0.5 * (up + down), 0.0, 1.0).normalized()).norm(), 1e-12);
}

TEST(Contact, NormalForceNeverPulls) {
  Coordinates q = Coordinates::Zero(), u = Coordinates::Zero();
  q[coord::z] = kBottomBelowG - 1e-4;  // 0.1 mm in
  u[coord::x] = 0.2;                   // sliding too, so friction would act if Fn did
  for (double rise : {1.0, 0.01, 1e-5}) {
    u[coord::z] = rise;
    const ForcesAt f = forces_at(q, u);
    const ContactParameters& k = f.model.parameters.contact;
    const double elastic = k.stiffness_k_g * std::pow(1e-4, k.exponent_sigma);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      ASSERT_EQ(f.contacts[leg].count, 1);
      const ContactPoint& c = f.contacts[leg].points[0];
      EXPECT_NEAR(c.penetration_rate_mps, -rise, 1e-12);
      EXPECT_GE(c.normal_force_N, 0.0);
      const double kelvin_voigt = elastic - k.damping_c_g * rise;
      if (kelvin_voigt < 0.0) {
        EXPECT_EQ(c.normal_force_N, 0.0) << "pulling out at " << rise << " m/s";
        EXPECT_EQ(c.friction_force_N, Vec3::Zero());
      } else {
        EXPECT_NEAR(c.normal_force_N, kelvin_voigt, 1e-12);
      }
    }
  }
}

TEST(Contact, FrictionOpposesSlip) {
  Coordinates q = Coordinates::Zero(), u = Coordinates::Zero();
  q[coord::z] = kBottomBelowG - 0.002;
  u[coord::x] = 0.3;
  u[coord::y] = -0.1;
  u[coord::yaw] = 0.2;
  for (int leg = 0; leg < kNumLegs; ++leg) u[coord::spin(leg)] = 2.0 * leg - 1.0;
  const ForcesAt f = forces_at(q, u);
  for (int leg = 0; leg < kNumLegs; ++leg) {
    ASSERT_EQ(f.contacts[leg].count, 1);
    const ContactPoint& c = f.contacts[leg].points[0];
    const Vec3 v = point_velocity(f.kin, node::wheel(leg), c.point_m);
    const Vec3 slip = v - v.dot(c.normal) * c.normal;
    EXPECT_LT((c.slip_velocity_mps - slip).norm(), 1e-14);
    ASSERT_GT(slip.norm(), 1e-3);
    EXPECT_LT(c.friction_force_N.dot(slip), 0.0) << "leg " << leg;
    EXPECT_NEAR(c.friction_force_N.dot(c.normal), 0.0, 1e-12);
    // Anti-parallel to the slip, of magnitude mu(|v_t|) F_n.
    EXPECT_LT(c.friction_force_N.cross(slip).norm(), 1e-12 * c.friction_force_N.norm() * slip.norm());
    EXPECT_NEAR(c.friction_force_N.norm(),
                makkar_mu(slip.norm(), f.model.parameters.friction.gammas) * c.normal_force_N, 1e-12);
  }
}

TEST(Contact, NormalForcesAloneAreThoseOfTheFullContact) {
  // compute_contact_normal_forces() is compute_contact_forces() up to the
  // friction: the same rates, slips and normal forces, bit for bit.
  Coordinates q = Coordinates::Zero(), u = Coordinates::Zero();
  q[coord::z] = kBottomBelowG - 0.002;
  u[coord::x] = 0.3;
  u[coord::z] = -0.05;
  u[coord::yaw] = 0.2;
  const ForcesAt f = forces_at(q, u);
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const NodeKinematics& wheel = f.kin.nodes[node::wheel(leg)];
    WheelContacts normal_only = find_wheel_contacts(f.model.terrain, wheel.origin, wheel.rotation.col(1),
                                                    f.model.parameters.geometry.wheel_radius_m);
    compute_contact_normal_forces(f.kin, node::wheel(leg), f.model.parameters.contact, normal_only);
    ASSERT_EQ(normal_only.count, 1);
    ASSERT_EQ(f.contacts[leg].count, 1);
    const ContactPoint& a = normal_only.points[0];
    const ContactPoint& b = f.contacts[leg].points[0];
    EXPECT_GT(a.normal_force_N, 0.0);
    EXPECT_EQ(a.normal_force_N, b.normal_force_N) << "leg " << leg;
    EXPECT_EQ(a.penetration_rate_mps, b.penetration_rate_mps) << "leg " << leg;
    EXPECT_EQ(a.slip_velocity_mps, b.slip_velocity_mps) << "leg " << leg;
    EXPECT_EQ(a.friction_force_N, Vec3::Zero());
  }
}

TEST(Contact, FrictionVanishesAtZeroSlip) {
  Coordinates q = Coordinates::Zero(), u = Coordinates::Zero();
  q[coord::z] = kBottomBelowG - 0.002;
  {  // At rest.
    const ForcesAt f = forces_at(q, u);
    for (const WheelContacts& w : f.contacts) {
      ASSERT_EQ(w.count, 1);
      EXPECT_GT(w.points[0].normal_force_N, 0.0);
      EXPECT_EQ(w.points[0].friction_force_N, Vec3::Zero());
    }
  }
  // Rolling without slip: v = omega R, the contact point is momentarily still.
  const double v = 0.7;
  u[coord::x] = v;
  for (int leg = 0; leg < kNumLegs; ++leg) u[coord::spin(leg)] = v / kRadius;
  const ForcesAt rolling = forces_at(q, u);
  for (const WheelContacts& w : rolling.contacts) {
    ASSERT_EQ(w.count, 1);
    EXPECT_LT(w.points[0].slip_velocity_mps.norm(), 1e-14);
    EXPECT_LT(w.points[0].friction_force_N.norm(), 1e-9 * w.points[0].normal_force_N);
  }
  // ... and it grows continuously from there.
  for (int leg = 0; leg < kNumLegs; ++leg) u[coord::spin(leg)] = (v - 1e-6) / kRadius;
  const ForcesAt slipping = forces_at(q, u);
  for (const WheelContacts& w : slipping.contacts) {
    const double mu = w.points[0].friction_force_N.norm() / w.points[0].normal_force_N;
    EXPECT_GT(mu, 0.0);
    EXPECT_LT(mu, 0.01);
    EXPECT_LT(w.points[0].friction_force_N.x(), 0.0);  // the rim slides forward: pushed back
  }
}

// Random states with contacts on flat ground and on a tilted plane grid.
std::vector<Terrain> test_terrains() {
  return {Terrain::flat(),
          Terrain::from_grid(testing::sampled_grid(-2.0, -2.0, 0.011, 0.013, 365, 310,
                                          [](double x, double y) { return 0.02 * x - 0.03 * y; }))};
}

// A random state over the middle of the test terrains, low enough that wheels touch.
void random_state_in_contact(std::mt19937& rng, Coordinates& q, Coordinates& u) {
  testing::random_state(rng, q, u);
  q[coord::x] *= 0.5;
  q[coord::y] *= 0.5;
  q[coord::z] = 0.21;
}

TEST(Contact, GeneralizedForceHasTheVirtualPowerOfTheContactForces) {
  std::mt19937 rng(21);
  int contacts_seen = 0;
  for (const Terrain& terrain : test_terrains()) {
    for (int trial = 0; trial < 6; ++trial) {
      Coordinates q, u;
      random_state_in_contact(rng, q, u);
      const ForcesAt f = forces_at(q, u, terrain);
      const Coordinates Q = contact_generalized_forces(f.model, f.kin, f.contacts);
      double power = 0.0;
      for (int leg = 0; leg < kNumLegs; ++leg)
        for (int k = 0; k < f.contacts[leg].count; ++k) {
          const ContactPoint& c = f.contacts[leg].points[k];
          power += (c.normal_force_N * c.normal + c.friction_force_N)
                       .dot(point_velocity(f.kin, node::wheel(leg), c.point_m));
          ++contacts_seen;
        }
      EXPECT_NEAR(Q.dot(u), power, 1e-10 * std::max(1.0, std::abs(power))) << "trial " << trial;
    }
  }
  EXPECT_GT(contacts_seen, 10);
}

TEST(Contact, GeneralizedForceIsTheFiniteDifferenceJacobianTransposed) {
  // J_P^T F with J_P = d P / d q for the material point P of the wheel at the
  // contact (u = dq/dt, docs/model.md §2).
  std::mt19937 rng(22);
  for (const Terrain& terrain : test_terrains()) {
    for (int trial = 0; trial < 4; ++trial) {
      Coordinates q, u;
      random_state_in_contact(rng, q, u);
      const ForcesAt f = forces_at(q, u, terrain);
      Coordinates expected = Coordinates::Zero();
      const double h = 1e-6;
      int count = 0;
      for (int leg = 0; leg < kNumLegs; ++leg) {
        const NodeKinematics& wheel = f.kin.nodes[node::wheel(leg)];
        for (int k = 0; k < f.contacts[leg].count; ++k) {
          const ContactPoint& c = f.contacts[leg].points[k];
          const Vec3 force = c.normal_force_N * c.normal + c.friction_force_N;
          const Vec3 body_fixed = wheel.rotation.transpose() * (c.point_m - wheel.origin);
          for (int i = 0; i < kNumCoordinates; ++i) {
            Coordinates qp = q, qm = q;
            qp[i] += h;
            qm[i] -= h;
            const Vec3 dP = (point_position(forward_kinematics(f.model.tree, qp, u), node::wheel(leg), body_fixed) -
                             point_position(forward_kinematics(f.model.tree, qm, u), node::wheel(leg), body_fixed)) /
                            (2.0 * h);
            expected[i] += dP.dot(force);
          }
          ++count;
        }
      }
      ASSERT_GT(count, 0) << "trial " << trial;
      const Coordinates Q = contact_generalized_forces(f.model, f.kin, f.contacts);
      EXPECT_LT((Q - expected).cwiseAbs().maxCoeff(), 1e-7 * std::max(1.0, expected.cwiseAbs().maxCoeff()))
          << "trial " << trial << "\nQ        " << Q.transpose() << "\nexpected " << expected.transpose();
    }
  }
}

TEST(Contact, ContactPointDerivativeEqualsFiniteDifferencesOnFlatGround) {
  // P is the lowest rim point: it moves with the wheel centre and the wheel
  // plane, not with the spin (the rim slides through it).
  const RoverModel model = make_rover_model(default_rover_parameters());
  std::mt19937 rng(29);
  for (int trial = 0; trial < 4; ++trial) {
    Coordinates q, u;
    testing::random_state(rng, q, u);
    for (int i = coord::yaw; i < kNumCoordinates; ++i) q[i] *= 0.02;  // every wheel 2 to 8 mm deep
    q[coord::z] = 0.2235;  // 5 mm below the wheels' reach at q = 0 (docs/model.md §3)
    const TreeKinematics kin = forward_kinematics(model.tree, q, u);
    const auto contacts = wheel_contacts(model, kin);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      ASSERT_EQ(contacts[leg].count, 1) << "trial " << trial << " leg " << leg;
      const int n = node::wheel(leg);
      const NodeKinematics& wheel = kin.nodes[n];
      const auto dP = contact_point_position_derivative(
          contacts[leg].points[0].point_m, wheel.origin, wheel.rotation.col(1),
          point_jacobian(model.tree, kin, n, wheel.origin), angular_jacobian(model.tree, kin, n));
      for (int k = 0; k < kNumCoordinates; ++k) {
        const double h = 1e-6;
        Coordinates qp = q, qm = q;
        qp[k] += h;
        qm[k] -= h;
        const Vec3 fd = (wheel_contacts(model, forward_kinematics(model.tree, qp, u))[leg].points[0].point_m -
                         wheel_contacts(model, forward_kinematics(model.tree, qm, u))[leg].points[0].point_m) /
                        (2.0 * h);
        EXPECT_LT((dP.col(k) - fd).norm(), 1e-7) << "trial " << trial << " leg " << leg << " coordinate " << k;
      }
      // Unlike the material point, P does not move with the wheel's spin.
      EXPECT_LT(dP.col(coord::spin(leg)).norm(), 1e-12);
    }
  }
}

}  // namespace
}  // namespace rover
