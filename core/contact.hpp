// Wheel-terrain contact (docs/model.md §6; paper sections 2.2.2-2.2.3, eqs. 7-9).
//
// The wheel is a disk of radius R_w in the plane through its centre normal to
// its spin axis. Contact regions are the maximal arcs of the rim below the
// terrain; in each, the contact point P is the rim point of maximum vertical
// depth d = h(P_x, P_y) - P_z, the penetration is p = d n_z with n the terrain
// normal at P, and the force is a Kelvin-Voigt normal force (never pulling)
// plus Makkar friction on the slip velocity, applied to the wheel at P.
#pragma once

#include <array>
#include <numbers>

#include "core/friction.hpp"
#include "core/kinematic_tree.hpp"
#include "core/rover_parameters.hpp"
#include "core/terrain.hpp"

namespace rover {

inline constexpr int kMaxContactsPerWheel = 4;
// Angular spacing of the rim samples that find contact regions on a height grid.
inline constexpr double kRimSamplingStep_rad = 2.0 * std::numbers::pi / 180.0;

struct ContactPoint {
  Vec3 point_m = Vec3::Zero();          // P, on the rim
  Vec3 normal = Vec3::UnitZ();          // terrain normal at P (unit)
  double depth_m = 0.0;                 // vertical depth d = h(P) - P_z > 0
  double penetration_m = 0.0;           // p = d n_z
  double penetration_rate_mps = 0.0;    // dp/dt = -v_P . n
  Vec3 slip_velocity_mps = Vec3::Zero();  // v_t = v_P - (v_P . n) n
  double normal_force_N = 0.0;          // F_n >= 0
  Vec3 friction_force_N = Vec3::Zero();   // F_t
  // makkar_tanh(|v_t|): set with F_t where there is friction (|v_t| > 0 and
  // F_n > 0), for mu and mu' at this state without new tanh.
  MakkarTanh friction_tanh;
};

struct WheelContacts {
  int count = 0;
  std::array<ContactPoint, kMaxContactsPerWheel> points;
  double total_normal_force_N() const {
    double sum = 0.0;
    for (int i = 0; i < count; ++i) sum += points[i].normal_force_N;
    return sum;
  }
};

// Geometry only: the deepest rim point of every region below the terrain
// (point, normal, depth, penetration). Exact (to round-off) on flat terrain;
// on a height grid, regions are found by sampling the lower rim and each
// deepest point is refined to round-off between its neighbouring samples
// (secant steps on the depth's slope, Brent's method where they fail).
WheelContacts find_wheel_contacts(const Terrain& terrain, const Vec3& wheel_centre_m,
                                  const Vec3& spin_axis, double wheel_radius_m);

// The number of regions find_wheel_contacts() finds (its `count`), without
// locating their deepest points: for checks that ask only whether and where
// a wheel touches (the stiff integrator's look inside a step).
int count_wheel_contact_regions(const Terrain& terrain, const Vec3& wheel_centre_m, const Vec3& spin_axis,
                                double wheel_radius_m);

// find_wheel_contacts() for the wheel of `leg`, at its frame in `kin`.
WheelContacts find_leg_wheel_contacts(const Terrain& terrain, const TreeKinematics& kin, int leg,
                                      double wheel_radius_m);
// The same, written into `contacts` without a copy of the result: its count,
// and each point it counts as a freshly found one (the points past the count
// are left as they were).
void find_leg_wheel_contacts(const Terrain& terrain, const TreeKinematics& kin, int leg, double wheel_radius_m,
                             WheelContacts& contacts);

// dP/dq (3 x 23) of a contact point P found by find_wheel_contacts(): the rim
// point at a fixed angle from the lowest rim point, which moves with the
// wheel centre and turns with the wheel plane but not with the wheel's spin
// (exact on flat terrain, where P is the lowest point). `centre_jacobian` and
// `angular_jacobian` are those of the wheel frame (kinematic_tree.hpp).
//
// It is dP/dq = centre_jacobian + T angular_jacobian, with T the 3 x 3 matrix
// [m/rad] of contact_point_turning() (zero for a wheel lying flat).
Eigen::Matrix<double, 3, kNumCoordinates> contact_point_position_derivative(
    const Vec3& contact_point_m, const Vec3& wheel_centre_m, const Vec3& spin_axis,
    const Eigen::Matrix<double, 3, kNumCoordinates>& centre_jacobian,
    const Eigen::Matrix<double, 3, kNumCoordinates>& angular_jacobian);

// T = dP/dtheta - dc/dtheta for a small rotation theta [rad] of the wheel frame
// (world axes): how P moves relative to the wheel centre c as the wheel plane
// turns. Column by column, dP/dq = dc/dq + T domega/du for the joints on the
// wheel's path (the same rotation per unit q as omega per unit u).
Mat3 contact_point_turning(const Vec3& contact_point_m, const Vec3& wheel_centre_m,
                           const Vec3& spin_axis);

// Completes the contacts of one wheel with velocities and forces.
// `wheel_node` is the node of the wheel body in the kinematic tree.
void compute_contact_forces(const TreeKinematics& kin, int wheel_node,
                            const ContactParameters& contact, const FrictionParameters& friction,
                            WheelContacts& contacts);

// The part of compute_contact_forces() before the friction: the penetration
// rates, slip velocities and normal forces (the same numbers); the friction
// forces are left as they are.
void compute_contact_normal_forces(const TreeKinematics& kin, int wheel_node,
                                   const ContactParameters& contact, WheelContacts& contacts);

}  // namespace rover
