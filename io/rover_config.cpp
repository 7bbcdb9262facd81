// See rover_config.hpp. Validation: masses and lengths positive, inertia
// tensors symmetric positive definite, stiffnesses and dampings non-negative,
// and every number within the scale of core/model_scale.hpp (beyond it, a
// unit mistake).
#include "io/rover_config.hpp"

#include <cmath>
#include <sstream>

#include <Eigen/Eigenvalues>

#include "core/model_scale.hpp"
#include "io/config_kind.hpp"

namespace rover::io {
namespace {

// Relative slack for the triangle inequality of the principal moments: a
// thin disk's rounded moments sit on it.
constexpr double kInertiaTriangleTolerance = 1e-6;

// `value` read from `key`, refused beyond +-`bound` (a unit mistake, `why`).
double within_scale(const JsonReader& r, const std::string& key, double value, double bound, const char* unit,
                    const std::string& why) {
  if (const std::string beyond = beyond_scale(value, bound, unit, why); !beyond.empty()) r.fail(key, beyond);
  return value;
}

// `value` read from `key`, refused below `bound` (a unit mistake, `why`).
double at_least(const JsonReader& r, const std::string& key, double value, double bound, const char* unit,
                const std::string& why) {
  if (const std::string below = below_scale(value, bound, unit, why); !below.empty()) r.fail(key, below);
  return value;
}

// A point or offset of the rover (m), each element within kMaxRoverLength_m.
Vec3 rover_length_vec3(const JsonReader& r, const std::string& key) {
  const Vec3 v = r.vec3(key);
  for (int i = 0; i < 3; ++i)
    if (const std::string beyond = beyond_scale(v(i), kMaxRoverLength_m, "m", kLengthScaleReason); !beyond.empty())
      r.fail(key, "element " + std::to_string(i) + ": " + beyond);
  return v;
}

RigidBodyParameters parse_body(const JsonReader& r) {
  RigidBodyParameters b;
  b.mass_kg = within_scale(r, "mass", r.positive("mass"), kMaxBodyMass_kg, "kg", kBodyMassScaleReason);
  at_least(r, "mass", b.mass_kg, kMinBodyMass_kg, "kg", kBodyMassScaleReason + " (tonnes?)");
  b.com_m = rover_length_vec3(r, "com");
  b.inertia_kgm2 = r.mat3("inertia");
  const Mat3& I = b.inertia_kgm2;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (const std::string beyond = beyond_scale(I(i, j), kMaxBodyInertia_kgm2, "kg m^2", kInertiaScaleReason);
          !beyond.empty())
        r.fail("inertia", "entry [" + std::to_string(i) + "][" + std::to_string(j) + "]: " + beyond);
  if ((I - I.transpose()).cwiseAbs().maxCoeff() > 1e-12 * std::max(1.0, I.cwiseAbs().maxCoeff()))
    r.fail("inertia", "inertia tensor is not symmetric");
  const Vec3 moments = Eigen::SelfAdjointEigenSolver<Mat3>(I, Eigen::EigenvaluesOnly).eigenvalues();  // ascending
  if (!(moments(0) > 0.0)) {
    std::ostringstream msg;
    msg << "inertia tensor is not positive definite (smallest eigenvalue " << moments(0) << ")";
    r.fail("inertia", msg.str());
  }
  // Every body's principal moments obey the triangle inequality (a thin disk
  // is the equality): a largest one beyond the sum of the others is no body.
  if (moments(2) > (moments(0) + moments(1)) * (1.0 + kInertiaTriangleTolerance))
    r.fail("inertia", "principal moments " + number_text(moments(0)) + ", " + number_text(moments(1)) + ", " +
                          number_text(moments(2)) + " kg m^2: the largest exceeds the sum of the other two, which "
                          "no rigid body can have");
  r.finish();
  return b;
}

template <std::size_t N>
std::array<double, N> non_negative_array(const JsonReader& r, const std::string& key) {
  const auto values = r.fixed_numbers<N>(key);
  for (std::size_t i = 0; i < N; ++i)
    if (!(values[i] >= 0.0)) r.fail(key, "element " + std::to_string(i) + " must not be negative");
  return values;
}

}  // namespace

double read_sharpness_f(const JsonReader& r, const std::string& key) {
  const double f = within_scale(r, key, r.positive(key), kMaxSharpness_per_rad, "1/rad", kSStructureScaleReason);
  if (f < kMinSharpness_per_rad)
    r.fail(key, number_text(f) + " 1/rad is below " + number_text(kMinSharpness_per_rad) + " 1/rad: " +
                    kSharpnessBelowScaleReason);
  return f;
}

double read_damping_c_q(const JsonReader& r, const std::string& key) {
  return within_scale(r, key, r.non_negative(key), kMaxDamping_Nms_per_rad, "N m s/rad", kSStructureScaleReason);
}

std::array<double, kNumSJoints> read_preloads(const JsonReader& r, const std::string& key) {
  const auto values = non_negative_array<kNumSJoints>(r, key);
  for (std::size_t i = 0; i < values.size(); ++i)
    if (const std::string beyond = beyond_scale(values[i], kMaxPreload_Nm, "N m", kSStructureScaleReason);
        !beyond.empty())
      r.fail(key, "element " + std::to_string(i) + ": " + beyond);
  return values;
}

namespace {

void parse_geometry(const JsonReader& g, RoverParameters& p) {
  p.geometry.bogie_pivot_m = rover_length_vec3(g, "bogie_pivot");
  p.geometry.hip_m = rover_length_vec3(g, "hip");
  p.geometry.knee_m = rover_length_vec3(g, "knee");
  p.geometry.wheel_centre_m = rover_length_vec3(g, "wheel_centre");
  p.geometry.wheel_radius_m =
      within_scale(g, "wheel_radius", g.positive("wheel_radius"), kMaxRoverLength_m, "m", kLengthScaleReason);
  at_least(g, "wheel_radius", p.geometry.wheel_radius_m, kMinWheelRadius_m, "m", kWheelRadiusBelowScaleReason);
  for (const char* key : {"hip", "knee"})
    if (!(g.vec3(key).norm() > 0.0)) g.fail(key, "link length must be positive");
  g.finish();
}

void parse_bodies(const JsonReader& bodies, RoverParameters& p) {
  p.chassis = parse_body(bodies.child("chassis"));
  p.bogie = parse_body(bodies.child("bogie"));
  p.module1 = parse_body(bodies.child("module1"));
  p.module2 = parse_body(bodies.child("module2"));
  p.wheel = parse_body(bodies.child("wheel"));
  bodies.finish();
}

void parse_s_structure(const JsonReader& s, RoverParameters& p) {
  p.s_structure.sharpness_f = read_sharpness_f(s, "f");
  p.s_structure.stiffness_Nm_per_rad = within_scale(s, "k_q", s.non_negative("k_q"),
                                                    kMaxSStructureStiffness_Nm_per_rad, "N m/rad", kJointScaleReason);
  p.s_structure.damping_c_q = read_damping_c_q(s, "c_q");
  // preload_order documents the order of preload_mean and preload_sd (docs/model.md §5);
  // it cannot change it, so any other order is an error rather than a silent relabelling.
  if (s.has("preload_order")) {
    const Json expected = {"11", "12", "21", "22", "31", "32", "41", "42"};
    if (s.raw("preload_order") != expected)
      s.fail("preload_order", "the preloads are always in the order " + expected.dump() +
                                  " (this key documents it and cannot change it)");
  }
  p.s_structure.preload_mean_Nm = read_preloads(s, "preload_mean");
  p.s_structure.preload_sd_Nm = read_preloads(s, "preload_sd");
  s.finish();
}

void parse_steering(const JsonReader& st, RoverParameters& p) {
  p.steering.stiffness_Nm_per_rad = within_scale(st, "K_d", st.non_negative("K_d"),
                                                  kMaxSteeringStiffness_Nm_per_rad, "N m/rad", kJointScaleReason);
  p.steering.damping_Nms_per_rad =
      within_scale(st, "D_d", st.non_negative("D_d"), kMaxDamping_Nms_per_rad, "N m s/rad", kJointScaleReason);
  p.steering.limit_rad =
      within_scale(st, "limit", st.positive("limit"), kMaxSteeringLimit_rad, "rad", kSteeringLimitScaleReason);
  p.steering.end_stop_stiffness_Nm_per_rad =
      within_scale(st, "end_stop_stiffness", st.non_negative("end_stop_stiffness"),
                   kMaxSteeringStiffness_Nm_per_rad, "N m/rad", kJointScaleReason);
  st.finish();
}

void parse_drive(const JsonReader& d, RoverParameters& p) {
  p.drive.gain_Nms_per_rad =
      within_scale(d, "K_w", d.non_negative("K_w"), kMaxDamping_Nms_per_rad, "N m s/rad", kJointScaleReason);
  p.drive.max_torque_Nm =
      within_scale(d, "tau_max", d.positive("tau_max"), kMaxDriveTorque_Nm, "N m", kDriveTorqueScaleReason);
  d.finish();
}

void parse_contact(const JsonReader& c, RoverParameters& p) {
  p.contact.stiffness_k_g =
      within_scale(c, "k_g", c.positive("k_g"), kMaxGroundStiffness, "N/m^sigma", kContactScaleReason);
  p.contact.damping_c_g = within_scale(c, "c_g", c.non_negative("c_g"), kMaxGroundDamping, "N s/m", kContactScaleReason);
  p.contact.exponent_sigma =
      within_scale(c, "sigma", c.positive("sigma"), kMaxContactExponent, "", kContactScaleReason);
  c.finish();
}

void parse_friction(const JsonReader& f, RoverParameters& p) {
  f.string_or("comment", "");
  p.friction.mu_static =
      within_scale(f, "mu_s", f.non_negative("mu_s"), kMaxFrictionCoefficient, "", kFrictionScaleReason);
  p.friction.v_static_mps =
      within_scale(f, "v_s", f.positive("v_s"), kMaxStribeckSpeed_mps, "m/s", kStribeckScaleReason);
  at_least(f, "v_s", p.friction.v_static_mps, kMinStribeckSpeed_mps, "m/s", kStribeckBelowScaleReason);
  p.friction.mu_kinetic =
      within_scale(f, "mu_k", f.non_negative("mu_k"), kMaxFrictionCoefficient, "", kFrictionScaleReason);
  p.friction.v_kinetic_mps =
      within_scale(f, "v_k", f.positive("v_k"), kMaxStribeckSpeed_mps, "m/s", kStribeckScaleReason);
  at_least(f, "v_k", p.friction.v_kinetic_mps, kMinStribeckSpeed_mps, "m/s", kStribeckBelowScaleReason);
  if (!(p.friction.v_kinetic_mps > p.friction.v_static_mps))
    f.fail("v_k", "must be larger than v_s (" + number_text(p.friction.v_static_mps) + " m/s)");
  if (f.has("gammas")) {
    p.friction.gammas = non_negative_array<6>(f, "gammas");
    p.friction.gammas_fitted_to = f.fixed_numbers<4>("gammas_fitted_to");
  } else {
    p.friction.gammas.fill(std::nan(""));  // synthesised by rover::friction_gammas_for
    p.friction.gammas_fitted_to.fill(std::nan(""));
  }
  f.finish();
}

}  // namespace

RoverParameters parse_rover_parameters(const Json& config, const std::string& file) {
  const JsonReader top(config, file);
  refuse_other_config_kind(config, file, ConfigKind::kRover);
  RoverParameters p;
  top.string_or("description", "");
  p.gravity_mps2 = within_scale(top, "gravity", top.non_negative("gravity"), kMaxGravity_mps2, "m/s^2",
                                kGravityScaleReason);
  parse_geometry(top.child("geometry"), p);
  parse_bodies(top.child("bodies"), p);
  parse_s_structure(top.child("s_structure"), p);
  parse_steering(top.child("steering"), p);
  parse_drive(top.child("drive"), p);
  parse_contact(top.child("contact"), p);
  parse_friction(top.child("friction"), p);
  top.finish();
  return p;
}

RoverParameters load_rover_parameters(const std::string& path) {
  return parse_rover_parameters(read_config_file(path, ConfigKind::kRover), path);
}

}  // namespace rover::io
