// Wheel-terrain contact detection and forces (see contact.hpp).
#include "core/contact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <boost/math/tools/minima.hpp>

#include "core/friction.hpp"

namespace rover {
namespace {

// Orthonormal basis of the wheel plane: `down` points to the lowest rim point
// (the rim point of largest -z), `along` = spin x down is horizontal.
struct RimFrame {
  Vec3 centre, down, along;
  double radius;
  Vec3 point(double angle) const {
    return centre + radius * (std::cos(angle) * down + std::sin(angle) * along);
  }
};

RimFrame rim_frame(const Vec3& centre, const Vec3& spin_axis, double radius) {
  RimFrame f{centre, Vec3::Zero(), Vec3::Zero(), radius};
  Vec3 down = -(Vec3::UnitZ() - spin_axis.z() * spin_axis);
  const double norm = down.norm();
  if (norm < 1e-12) {  // wheel lying flat: every rim point is equally low
    down = spin_axis.unitOrthogonal();
  } else {
    down /= norm;
  }
  f.down = down;
  f.along = spin_axis.cross(down);
  return f;
}

double vertical_depth(const Terrain& terrain, const Vec3& p) {
  return terrain.height(p.x(), p.y()) - p.z();
}

// The deepest point of a region is where the depth's slope along the rim,
//   d'(a) = grad h(P(a)) . dP_xy/da - dP_z/da,
// changes sign. On a terrain face it is smooth, and a few secant steps from
// the deepest rim sample find its root to round-off (a step shorter than
// kSettled_rad ends them); the root is taken if it lies between the
// neighbouring samples and is at least as deep as the deepest one. Where the
// steps do not settle (a kink of the terrain between the samples, where the
// slope jumps), Brent's method finds the deepest point to about sqrt(eps) of
// the angle, and the same secant steps refine it within kRefineReach_rad
// (snap_to_grid_line() then decides at a kink). Brent's point alone would not
// do: where it stops changes in steps as the wheel moves, so the contact
// point, and with it the moment of the contact force, would jitter by ~1e-9 m
// from one right-hand side to the next, a noise of ~1e-4 m/s^2 in du/dt that
// holds an explicit integrator at tight tolerance to steps of 1e-8 s.
constexpr double kRefineReach_rad = 1e-4, kRefineDelta_rad = 1e-7;
constexpr int kRefineIterations = 8;
constexpr double kSettled_rad = 1e-13;

double depth_slope_along_rim(const Terrain& terrain, const RimFrame& rim, double angle) {
  const Vec3 p = rim.point(angle);
  const Vec3 dp = rim.radius * (-std::sin(angle) * rim.down + std::cos(angle) * rim.along);
  const Eigen::Vector2d g = terrain.gradient(p.x(), p.y());
  return g.x() * dp.x() + g.y() * dp.y() - dp.z();
}

// Root of the depth's slope along the rim by secant steps from `start`,
// kept within [lo, hi]; NaN if they leave it or do not settle to round-off
// within kRefineIterations.
double slope_root_along_rim(const Terrain& terrain, const RimFrame& rim, double start, double lo, double hi) {
  double a0 = start, a1 = start + kRefineDelta_rad;
  double s0 = depth_slope_along_rim(terrain, rim, a0), s1 = depth_slope_along_rim(terrain, rim, a1);
  for (int it = 0; it < kRefineIterations; ++it) {
    if (s1 == 0.0) return a1;
    if (s1 == s0) break;
    const double a2 = a1 - s1 * (a1 - a0) / (s1 - s0);
    if (!(a2 >= lo && a2 <= hi)) break;
    if (std::abs(a2 - a1) <= kSettled_rad) return a2;
    a0 = a1;
    s0 = s1;
    a1 = a2;
    s1 = depth_slope_along_rim(terrain, rim, a1);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// The deepest angle refined from `angle` (of depth `depth`) within
// kRefineReach_rad: the slope's root if it is at least as deep, else `angle`.
double refine_deepest_angle(const Terrain& terrain, const RimFrame& rim, double angle, double depth) {
  const double a = slope_root_along_rim(terrain, rim, angle, angle - kRefineReach_rad, angle + kRefineReach_rad);
  return !std::isnan(a) && vertical_depth(terrain, rim.point(a)) >= depth - 1e-15 ? a : angle;
}

// On a height grid the depth along the rim has kinks where the rim crosses a
// grid line, and at a convex edge its maximum sits on such a kink. Brent's
// method stops within ~1e-9 m of it, on either side, which would make the
// normal chatter between the one-sided slopes and their mean. If the optimum is
// within kSnapDistance_m of a grid line, the exact crossing of the rim with the
// line is taken instead when the depth rises towards it from both sides: its
// slope along the rim, taken kOffLine_m off the line on either side (beyond
// the terrain's grid-line tolerance, so on each side's own slope), is >= 0
// before it and <= 0 after it. Comparing the depths instead would decide at
// round-off where the wheel's tangent point on a face nears the edge (both
// depths agree to 1e-15 m there): the contact would flip between the face's
// normal and the edge's from one right-hand side to the next, a jump that no
// step, however short, could step across. A line where the slope does not
// jump (one-sided slopes along the rim within kKinkSlopeStep_m [m/rad]; a
// kink of the obstacle's ramp makes them differ by ~1e-3 or more) is left to
// the refined optimum.
constexpr double kSnapDistance_m = 1e-6, kOffLine_m = 1e-8, kKinkSlopeStep_m = 1e-6;

// Rim angle near `angle` where the rim coordinate `axis` (0 = x, 1 = y) equals
// `line` (Newton's method); returns `angle` if it does not converge.
double rim_angle_on_line(const RimFrame& rim, int axis, double line, double angle) {
  double a = angle;
  for (int it = 0; it < 8; ++it) {
    const double f = rim.centre[axis] + rim.radius * (std::cos(a) * rim.down[axis] + std::sin(a) * rim.along[axis]) - line;
    const double df = rim.radius * (-std::sin(a) * rim.down[axis] + std::cos(a) * rim.along[axis]);
    if (std::abs(df) < 1e-12) return angle;
    a -= f / df;
    if (std::abs(f) < 1e-15) break;
  }
  return std::abs(a - angle) < 1e-3 ? a : angle;
}

double snap_to_grid_line(const Terrain& terrain, const RimFrame& rim, double angle) {
  const HeightGrid& g = *terrain.grid();
  double best_angle = angle;
  double best_depth = vertical_depth(terrain, rim.point(angle));
  for (int axis = 0; axis < 2; ++axis) {
    const double origin = axis == 0 ? g.origin_x_m : g.origin_y_m;
    const double spacing = axis == 0 ? g.spacing_x_m : g.spacing_y_m;
    const Vec3 p = rim.point(best_angle);
    const double line = origin + std::round((p[axis] - origin) / spacing) * spacing;
    if (std::abs(p[axis] - line) > kSnapDistance_m) continue;
    const double a = rim_angle_on_line(rim, axis, line, best_angle);
    const double d = vertical_depth(terrain, rim.point(a));
    const double across = std::abs(rim.radius * (-std::sin(a) * rim.down[axis] + std::cos(a) * rim.along[axis]));
    bool rises_to_line = d >= best_depth - 1e-15;  // the rim runs along the line: by depth
    if (across * kSnapDistance_m > kOffLine_m) {
      const double before = depth_slope_along_rim(terrain, rim, a - kOffLine_m / across);
      const double after = depth_slope_along_rim(terrain, rim, a + kOffLine_m / across);
      rises_to_line = before >= 0.0 && after <= 0.0 && before - after > kKinkSlopeStep_m;
    }
    if (rises_to_line) {
      best_angle = a;
      best_depth = d;
    }
  }
  return best_angle;
}

// The regions of the rim below the terrain. On a flat plane the lowest rim
// point is the deepest, exactly. On a height grid only the rim arc below the
// highest terrain point nearby can touch, z(angle) = c_z + R cos(angle) down_z
// with down_z <= 0, and regions are runs of samples kRimSamplingStep_rad
// apart below the terrain: a region thinner than that is at most
// R (1 - cos(step / 2)) deep (0.013 mm for 2 degrees and R = 85 mm: a force
// of about 2 mN), and is picked up as it deepens. For each region (at most
// kMaxContactsPerWheel), on_region(angle, depth, lo, hi) gets the angle and
// depth of its deepest sample and the angles of the samples on either side of
// it (on a flat plane the lowest point, exact: lo = hi = angle = 0); returns
// their number.
template <class OnRegion>
int for_each_region(const Terrain& terrain, const RimFrame& rim, const Vec3& spin_axis, OnRegion&& on_region) {
  if (terrain.is_flat()) {
    const double depth = terrain.flat_height() - rim.point(0.0).z();
    if (!(depth > 0.0)) return 0;
    on_region(0.0, depth, 0.0, 0.0);
    return 1;
  }
  const Vec3& centre = rim.centre;
  const double reach_x = rim.radius * std::sqrt(std::max(0.0, 1.0 - spin_axis.x() * spin_axis.x()));
  const double reach_y = rim.radius * std::sqrt(std::max(0.0, 1.0 - spin_axis.y() * spin_axis.y()));
  const double max_height =
      terrain.max_height_in(centre.x() - reach_x, centre.x() + reach_x, centre.y() - reach_y, centre.y() + reach_y);
  const double down_z = rim.down.z();
  double half_arc = std::numbers::pi;
  if (down_z < -1e-12) {
    const double c = (max_height - centre.z()) / (rim.radius * down_z);
    if (c >= 1.0) return 0;  // the whole rim is above the terrain
    half_arc = c <= -1.0 ? std::numbers::pi : std::acos(c);
  }
  const int n = std::max(2, static_cast<int>(std::ceil(2.0 * half_arc / kRimSamplingStep_rad)));
  const double h = 2.0 * half_arc / n;
  auto depth_at = [&](double angle) { return vertical_depth(terrain, rim.point(angle)); };

  int regions = 0;
  int i = 0;
  while (i <= n && regions < kMaxContactsPerWheel) {
    double d = depth_at(-half_arc + i * h);
    if (!(d > 0.0)) {
      ++i;
      continue;
    }
    // A region starts at sample i: follow it, remember its deepest sample.
    int best = i;
    double best_depth = d;
    while (++i <= n) {
      d = depth_at(-half_arc + i * h);
      if (!(d > 0.0)) break;
      if (d > best_depth) {
        best_depth = d;
        best = i;
      }
    }
    on_region(-half_arc + best * h, best_depth, -half_arc + (best - 1) * h, -half_arc + (best + 1) * h);
    ++regions;
  }
  return regions;
}

}  // namespace

namespace {

// find_wheel_contacts() into `out` (see find_leg_wheel_contacts()).
void find_contacts_into(const Terrain& terrain, const Vec3& wheel_centre_m, const Vec3& spin_axis,
                        double wheel_radius_m, WheelContacts& out) {
  out.count = 0;
  const RimFrame rim = rim_frame(wheel_centre_m, spin_axis, wheel_radius_m);
  auto depth_at = [&](double angle) { return vertical_depth(terrain, rim.point(angle)); };
  for_each_region(terrain, rim, spin_axis, [&](double sample_angle, double sample_depth, double lo, double hi) {
    ContactPoint& c = out.points[out.count++];
    c = ContactPoint{};
    if (terrain.is_flat()) {  // the lowest rim point, exactly
      c.point_m = rim.point(0.0);
      c.normal = Vec3::UnitZ();
      c.depth_m = sample_depth;
      c.penetration_m = sample_depth;
      return;
    }
    // The deepest point between the neighbouring samples: the root of the
    // depth's slope from the deepest sample if it settles there, else Brent's
    // method refined as above (kinks; see the top of this section).
    double best_angle = slope_root_along_rim(terrain, rim, sample_angle, lo, hi);
    if (std::isnan(best_angle) || !(depth_at(best_angle) >= sample_depth - 1e-15)) {
      const auto [angle, neg_depth] = boost::math::tools::brent_find_minima(
          [&](double a) { return -depth_at(a); }, lo, hi, std::numeric_limits<double>::digits / 2);
      best_angle = -neg_depth < sample_depth ? sample_angle : angle;  // keep the better sample
      best_angle = refine_deepest_angle(terrain, rim, best_angle, std::max(-neg_depth, sample_depth));
    }
    best_angle = snap_to_grid_line(terrain, rim, best_angle);
    c.point_m = rim.point(best_angle);
    c.depth_m = vertical_depth(terrain, c.point_m);
    c.normal = terrain.normal(c.point_m.x(), c.point_m.y());
    c.penetration_m = c.depth_m * c.normal.z();
  });
}

}  // namespace

WheelContacts find_wheel_contacts(const Terrain& terrain, const Vec3& wheel_centre_m,
                                  const Vec3& spin_axis, double wheel_radius_m) {
  WheelContacts out;
  find_contacts_into(terrain, wheel_centre_m, spin_axis, wheel_radius_m, out);
  return out;
}

int count_wheel_contact_regions(const Terrain& terrain, const Vec3& wheel_centre_m, const Vec3& spin_axis,
                                double wheel_radius_m) {
  return for_each_region(terrain, rim_frame(wheel_centre_m, spin_axis, wheel_radius_m), spin_axis,
                         [](double, double, double, double) {});
}

WheelContacts find_leg_wheel_contacts(const Terrain& terrain, const TreeKinematics& kin, int leg,
                                      double wheel_radius_m) {
  WheelContacts out;
  find_leg_wheel_contacts(terrain, kin, leg, wheel_radius_m, out);
  return out;
}

void find_leg_wheel_contacts(const Terrain& terrain, const TreeKinematics& kin, int leg, double wheel_radius_m,
                             WheelContacts& contacts) {
  const NodeKinematics& wheel = kin.nodes[node::wheel(leg)];
  find_contacts_into(terrain, wheel.origin, wheel.rotation.col(1), wheel_radius_m, contacts);
}

Mat3 contact_point_turning(const Vec3& contact_point_m, const Vec3& wheel_centre_m,
                           const Vec3& spin_axis) {
  // rim_frame(): down = -w / |w| with w = z - a_z a, along = a x down, and
  // P - c = r_down down + r_along along at fixed r_down, r_along. Per unit
  // rotation theta of the frame the axis turns by da = -[a]x theta, and
  //   dw = -(a z^T + a_z I) da,  d down = -(I - down down^T) dw / |w|,
  //   d along = -[down]x da + [a]x d down.
  const Vec3 w = Vec3::UnitZ() - spin_axis.z() * spin_axis;
  const double w_norm = w.norm();
  if (w_norm < 1e-12) return Mat3::Zero();  // wheel lying flat: no lowest point
  const Vec3 down = -w / w_norm, along = spin_axis.cross(down);
  const Mat3 d_axis = -cross_matrix(spin_axis);
  const Mat3 d_w = -(spin_axis * Vec3::UnitZ().transpose() + spin_axis.z() * Mat3::Identity()) * d_axis;
  const Mat3 d_down = -((Mat3::Identity() - down * down.transpose()) / w_norm) * d_w;
  const Mat3 d_along = -cross_matrix(down) * d_axis + cross_matrix(spin_axis) * d_down;
  const Vec3 r = contact_point_m - wheel_centre_m;
  return r.dot(down) * d_down + r.dot(along) * d_along;
}

Eigen::Matrix<double, 3, kNumCoordinates> contact_point_position_derivative(
    const Vec3& contact_point_m, const Vec3& wheel_centre_m, const Vec3& spin_axis,
    const Eigen::Matrix<double, 3, kNumCoordinates>& centre_jacobian,
    const Eigen::Matrix<double, 3, kNumCoordinates>& angular_jacobian) {
  return centre_jacobian +
         contact_point_turning(contact_point_m, wheel_centre_m, spin_axis).lazyProduct(angular_jacobian);
}

void compute_contact_normal_forces(const TreeKinematics& kin, int wheel_node,
                                   const ContactParameters& contact, WheelContacts& contacts) {
  for (int k = 0; k < contacts.count; ++k) {
    ContactPoint& c = contacts.points[k];
    const Vec3 v = point_velocity(kin, wheel_node, c.point_m);
    const double vn = v.dot(c.normal);
    c.penetration_rate_mps = -vn;
    c.slip_velocity_mps = v - vn * c.normal;
    const double p = std::max(c.penetration_m, 0.0);
    c.normal_force_N = std::max(0.0, contact.stiffness_k_g * std::pow(p, contact.exponent_sigma) +
                                         contact.damping_c_g * c.penetration_rate_mps);
  }
}

void compute_contact_forces(const TreeKinematics& kin, int wheel_node,
                            const ContactParameters& contact, const FrictionParameters& friction,
                            WheelContacts& contacts) {
  compute_contact_normal_forces(kin, wheel_node, contact, contacts);
  for (int k = 0; k < contacts.count; ++k) {
    ContactPoint& c = contacts.points[k];
    const double slip = c.slip_velocity_mps.norm();
    c.friction_force_N.setZero();
    c.friction_tanh = {};
    if (slip > 0.0 && c.normal_force_N > 0.0) {
      c.friction_tanh = makkar_tanh(slip, friction.gammas);
      c.friction_force_N =
          -(makkar_mu(slip, friction.gammas, c.friction_tanh) * c.normal_force_N / slip) * c.slip_velocity_mps;
    }
  }
}

}  // namespace rover
