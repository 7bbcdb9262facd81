// Wheel-terrain contact detection and forces (see contact.hpp).
#include "core/contact.hpp"

#include <cmath>

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

}  // namespace

WheelContacts find_wheel_contacts(const Terrain& terrain, const Vec3& wheel_centre_m,
                                  const Vec3& spin_axis, double wheel_radius_m) {
  WheelContacts out;
  const RimFrame rim = rim_frame(wheel_centre_m, spin_axis, wheel_radius_m);

  if (terrain.is_flat()) {
    // Horizontal plane: the lowest rim point is the deepest, exactly.
    const Vec3 p = rim.point(0.0);
    const double depth = terrain.flat_height() - p.z();
    if (depth > 0.0) {
      ContactPoint& c = out.points[out.count++];
      c.point_m = p;
      c.normal = Vec3::UnitZ();
      c.depth_m = depth;
      c.penetration_m = depth;
    }
    return out;
  }

  // Height grid. Only the rim arc below the highest terrain point can touch:
  // z(angle) = c_z + R cos(angle) down_z with down_z <= 0.
  const HeightGrid* grid = terrain.grid();
  const double max_height = terrain.max_height();
  const double down_z = rim.down.z();
  double half_arc = M_PI;
  if (down_z < -1e-12) {
    const double c = (max_height - wheel_centre_m.z()) / (wheel_radius_m * down_z);
    if (c >= 1.0) return out;  // the whole rim is above the terrain
    half_arc = c <= -1.0 ? M_PI : std::acos(c);
  }
  // Sample the arc at most every 2 degrees and at most every half grid spacing.
  const double spacing = std::min(grid->spacing_x_m, grid->spacing_y_m);
  const double step = std::min(M_PI / 90.0, 0.5 * spacing / wheel_radius_m);
  const int n = std::max(8, static_cast<int>(std::ceil(2.0 * half_arc / step)));
  const double h = 2.0 * half_arc / n;
  auto depth_at = [&](double angle) { return vertical_depth(terrain, rim.point(angle)); };

  int i = 0;
  while (i <= n && out.count < kMaxContactsPerWheel) {
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
    // Refine the deepest point between the neighbouring samples (Brent).
    const double lo = -half_arc + (best - 1) * h, hi = -half_arc + (best + 1) * h;
    const auto [angle, neg_depth] = boost::math::tools::brent_find_minima(
        [&](double a) { return -depth_at(a); }, lo, hi, std::numeric_limits<double>::digits / 2);
    double best_angle = angle;
    if (-neg_depth < best_depth) best_angle = -half_arc + best * h;  // keep the better sample
    const Vec3 p = rim.point(best_angle);
    ContactPoint& c = out.points[out.count++];
    c.point_m = p;
    c.depth_m = vertical_depth(terrain, p);
    c.normal = terrain.normal(p.x(), p.y());
    c.penetration_m = c.depth_m * c.normal.z();
  }
  return out;
}

void compute_contact_forces(const TreeKinematics& kin, int wheel_node,
                            const ContactParameters& contact, const FrictionParameters& friction,
                            WheelContacts& contacts) {
  for (int k = 0; k < contacts.count; ++k) {
    ContactPoint& c = contacts.points[k];
    const Vec3 v = point_velocity(kin, wheel_node, c.point_m);
    const double vn = v.dot(c.normal);
    c.penetration_rate_mps = -vn;
    c.slip_velocity_mps = v - vn * c.normal;
    const double p = std::max(c.penetration_m, 0.0);
    c.normal_force_N = std::max(0.0, contact.stiffness_k_g * std::pow(p, contact.exponent_sigma) +
                                         contact.damping_c_g * c.penetration_rate_mps);
    const double slip = c.slip_velocity_mps.norm();
    c.friction_force_N.setZero();
    if (slip > 0.0 && c.normal_force_N > 0.0)
      c.friction_force_N =
          -(makkar_mu(slip, friction.gammas) * c.normal_force_N / slip) * c.slip_velocity_mps;
  }
}

}  // namespace rover
