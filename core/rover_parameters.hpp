// Rover parameters: every number of docs/model.md §3–5 as plain data.
//
// Geometry and mass properties are given for the template leg (front-left) and
// the left bogie; mirrored_position()/mirrored_inertia() apply docs/model.md §1
// (S = diag(s_x, s_y, 1); r -> S r, I -> S I S) for the other legs and the
// right bogie. Nothing here is a constant of the code: the loader (io/) fills
// these structs from configs/rover.json.
#pragma once

#include <array>
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rover {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

inline constexpr int kNumLegs = 4;
inline constexpr int kNumSJoints = 8;  // two S-structure joints per leg

// Mass properties of one rigid body, about its own centre of mass, in its frame.
struct RigidBodyParameters {
  double mass_kg = 0.0;
  Vec3 com_m = Vec3::Zero();            // centre of mass in the body frame
  Mat3 inertia_kgm2 = Mat3::Zero();     // about the centre of mass, body axes
};

// Kinematic tree geometry (docs/model.md §3), template leg / left bogie.
struct RoverGeometry {
  Vec3 bogie_pivot_m{0.0, 0.1325, -0.030};     // P_s in the chassis frame
  Vec3 hip_m{0.1078, 0.0, -0.0265};            // H_j in the bogie frame
  Vec3 knee_m{0.0842, 0.0, -0.0540};           // K_j in the module-1 frame
  Vec3 wheel_centre_m{0.168, 0.089, -0.033};   // C_j in the module-2 frame
  double wheel_radius_m = 0.085;
};

// S-structure lumped joint (eq. 1 plus viscous term, docs/model.md §5):
// tau = -(2 M0 / pi) atan(f b) - k_q b - c_q db/dt.
struct SStructureParameters {
  double sharpness_f = 1e4;                      // f [1/rad]
  double stiffness_Nm_per_rad = 9.91;            // k_q
  double damping_c_q = 0.14;                     // c_q [N m s/rad]
  // Preloads M0 in the order (1,1), (1,2), (2,1), (2,2), (3,1), (3,2), (4,1), (4,2).
  std::array<double, kNumSJoints> preload_mean_Nm{1.924, 1.336, 2.096, 1.221,
                                                  1.725, 1.480, 2.048, 1.117};
  std::array<double, kNumSJoints> preload_sd_Nm{0.039, 0.046, 0.089, 0.031,
                                                0.069, 0.053, 0.075, 0.032};
};

// Steering servo (position control with end-stops), docs/model.md §5.
struct SteeringParameters {
  double stiffness_Nm_per_rad = 20.0;            // K_d
  double damping_Nms_per_rad = 0.2;              // D_d
  double limit_rad = 1.7453;                     // |d_j| <= limit
  double end_stop_stiffness_Nm_per_rad = 200.0;  // per rad beyond the limit
};

// Wheel drive (velocity control, smooth saturation), docs/model.md §5.
struct DriveParameters {
  double gain_Nms_per_rad = 0.3;                 // K_w
  double max_torque_Nm = 4.1;                    // tau_max
};

// Kelvin-Voigt normal contact (eq. 7), docs/model.md §6.
struct ContactParameters {
  double stiffness_k_g = 1e6;                    // N/m^sigma
  double damping_c_g = 100.0;                    // N s/m
  double exponent_sigma = 1.8;
};

// Makkar friction (eq. 8): engineering parameters and the fitted gammas.
// `gammas` are used as they are only while the engineering parameters equal
// `gammas_fitted_to` (mu_s, v_s, mu_k, v_k) exactly and the fit passes the
// quality bar; otherwise rover::friction_gammas_for() synthesises a new set.
struct FrictionParameters {
  double mu_static = 0.3;
  double v_static_mps = 5.5e-4;
  double mu_kinetic = 0.2;
  double v_kinetic_mps = 2e-3;
  std::array<double, 6> gammas{0.9264631218718848, 1831.8163703630614,
                               1062.6242130578348, 0.20009963867985064,
                               730.7116335954703, 0.0};
  std::array<double, 4> gammas_fitted_to{0.3, 5.5e-4, 0.2, 2e-3};
};

struct RoverParameters {
  double gravity_mps2 = 9.81;
  RoverGeometry geometry;
  RigidBodyParameters chassis;
  RigidBodyParameters bogie;     // template: left bogie
  RigidBodyParameters module1;   // template: front-left leg
  RigidBodyParameters module2;
  RigidBodyParameters wheel;
  SStructureParameters s_structure;
  SteeringParameters steering;
  DriveParameters drive;
  ContactParameters contact;
  FrictionParameters friction;
};

// The defaults of docs/model.md (the same numbers as configs/rover.json); for tests
// and as the base that the JSON loader overwrites field by field.
RoverParameters default_rover_parameters();

// Leg sign conventions (docs/model.md §1): legs 0..3 are 1 = FL, 2 = FR, 3 = RL, 4 = RR.
inline constexpr double leg_sign_x(int leg) { return leg < 2 ? 1.0 : -1.0; }
inline constexpr double leg_sign_y(int leg) { return (leg % 2 == 0) ? 1.0 : -1.0; }

inline Vec3 mirrored_position(const Vec3& r, double s_x, double s_y) {
  return Vec3(s_x * r.x(), s_y * r.y(), r.z());
}
inline Mat3 mirrored_inertia(const Mat3& inertia, double s_x, double s_y) {
  const Eigen::DiagonalMatrix<double, 3> S(s_x, s_y, 1.0);
  return S * inertia * S;
}

}  // namespace rover
