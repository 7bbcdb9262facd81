// The linearly implicit integrator of the SA model (docs/model.md §9;
// declared in integrators.hpp): the Rosenbrock-W method ROS34PW2, or the
// fourth-order Rosenbrock method RODAS4 by settings.method (both in
// rosenbrock_w.hpp; the step control below is the same, on the embedded
// solution of either), with the stiff force elements linearized analytically
// (force_jacobian.hpp), the mass matrix of the step start in the iteration
// matrix M0 - h g D - h^2 g^2 K (23 x 23, one LU per step size tried, without
// fill-in on the coordinate tree: branch_induced_lu.hpp), step
// control on the embedded second-order solution, and cubic Hermite output.
//
// Error control, on the embedded second-order solution:
//  * positions: the max norm of the dopri5 control, e_i / (atol + rtol |x_i|);
//  * speeds: the same, except that
//    - the chassis's yaw, pitch and roll rates are held to atol / r, r the
//      distance from the chassis origin to the farthest wheel centre (at the
//      start), so that the speed they give the wheels is held to atol, as the
//      chassis's own speed is. (A wheel's spin rate in the air held to
//      atol / radius in the same way saves another 9 % of the drop's
//      right-hand sides, but the integration error then moves a damping fit
//      to synthetic skewed-drop data by two standard errors.)
//    - a speed error is measured by the
//    displacement it makes within the time it acts, min(1 / omega_c, 1 s),
//    where omega_c = sqrt(-k_cc / M_cc) is the local frequency of coordinate c
//    on its stiff springs (an S-structure in its preload region, a loaded
//    contact; k is the springs' part of K, without the friction's, which
//    drives a creep, not an oscillation). Non-stiff speeds are held to atol
//    as by dopri5, but a 3 kHz ringing of an S-structure joint, whose speed
//    is 2e4 times its displacement, is not followed to the last
//    micro-radian per second;
//  * slip: at every contact of the step start, the error of the slip speed,
//    (I - n n^T) J_P e_u, is held to settings.slip_tolerance (5 % by
//    default) of the speed scale on which the friction force changes: v_s
//    near stick, about |v_t| in gross sliding (slip_error_norm() below);
//  * wheel spin: a disk wheel's rolling angle enters no force, and its rate
//    matters through the speed of its rim. A wheel on the ground is measured
//    by its slip alone; a wheel in the air by its absolute rate about its
//    axis, not by the rate relative to the leg, which follows every ringing
//    of the S-joints above it (wheel_spin_rows() below).
// The third-order solution that is kept is much better than the estimate, so
// this integrator wants looser tolerances than dopri5 for the same accuracy
// (default_integrator_settings(): rtol 1e-5, atol 2e-4).
//
// Touchdown: the normal force jumps from 0 to c_g dp/dt when a wheel starts to
// touch. A step whose stages all miss the contact, but whose end state has it,
// has skipped part of the impact without its error estimate noticing; such a
// step is rejected and retried at half the size, until a stage sees the
// contact and the error estimate takes over. A try whose stages see a contact
// region that the start did not have is retried, once per step, where the
// motion of the start (q0 + s u0 + s^2 a0 / 2) meets it (predicted_touchdown()):
// the step then ends just before the touchdown and the next one starts at
// it, where creeping up to it by the error estimate's shrinking (at most 5
// per try) costs about ten rejected tries. A contact can also begin and end
// inside one step, between its stages (a wheel that strikes the foot of a ramp
// and bounces off it within a millisecond): the accepted step is looked inside,
// at a quarter, half and three quarters of it on the cubic Hermite output, and
// a contact region there that no evaluated point of the step had (poses only,
// count_wheel_contact_regions()) rejects the step in the same way. A wheel
// that already had as many regions as it can have (one on a flat plane) is not
// looked at: the horizontal drop, whose wheels are down after the landing,
// spends 2 % of its instructions on it (docs/performance.md, "Contacts inside
// a step").
//
// Work per accepted step: the right-hand side at the step start (which also
// gives M0, F0 and the contacts), one assembly of D and K from the contacts'
// point Jacobians, one sparse 23 x 23 LU, and three right-hand sides for the
// stages, which need du/dt but not M and so take it from the articulated-body
// recursion (articulated_body.hpp) without forming M.
// Every right-hand side is counted in the report's rhs_evaluations, and so is
// each Jacobian assembly, as one evaluation (it costs about as much as one
// right-hand side; bench/integrator_bench.cpp times both).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include <Eigen/Cholesky>

#include "core/branch_induced_lu.hpp"
#include "core/dynamics.hpp"
#include "core/equations_of_motion.hpp"
#include "core/force_jacobian.hpp"
#include "core/friction.hpp"
#include "core/integrators.hpp"
#include "core/number_text.hpp"
#include "core/rosenbrock_w.hpp"
#include "core/s_structure.hpp"

namespace rover {
namespace {

using ContactCounts = std::array<int, kNumLegs>;

// Contacts that push (F_n > 0), per wheel.
ContactCounts active_contacts(const std::array<WheelContacts, kNumLegs>& contacts) {
  ContactCounts n{};
  for (int leg = 0; leg < kNumLegs; ++leg)
    for (int k = 0; k < contacts[leg].count; ++k)
      n[leg] += contacts[leg].points[k].normal_force_N > 0.0 ? 1 : 0;
  return n;
}

// Contact regions, pushing or not, per wheel.
ContactCounts contact_regions(const std::array<WheelContacts, kNumLegs>& contacts) {
  ContactCounts n{};
  for (int leg = 0; leg < kNumLegs; ++leg) n[leg] = contacts[leg].count;
  return n;
}

// Whether a state that was not evaluated has a contact region that no
// evaluated point of its step had (`seen`), from the poses alone
// (`kinematics` is scratch). A wheel that already had as many regions as it
// can have (one on a flat plane) is not looked at, nor is the tree when no
// wheel is left.
int most_regions_per_wheel(const RoverModel& model) { return model.terrain.is_flat() ? 1 : kMaxContactsPerWheel; }

bool every_wheel_has_most_regions(const RoverModel& model, const ContactCounts& seen) {
  const int most = most_regions_per_wheel(model);
  return std::all_of(seen.begin(), seen.end(), [&](int n) { return n >= most; });
}

bool has_unseen_region(const RoverModel& model, const StateVector& x, const ContactCounts& seen,
                       TreeKinematics& kinematics) {
  const int most = most_regions_per_wheel(model);
  if (every_wheel_has_most_regions(model, seen)) return false;
  forward_pose_and_velocity(model.tree, x.head<kNumCoordinates>(), x.tail<kNumCoordinates>(), kinematics);
  for (int leg = 0; leg < kNumLegs; ++leg) {
    if (seen[leg] >= most) continue;
    const NodeKinematics& wheel = kinematics.nodes[node::wheel(leg)];
    if (count_wheel_contact_regions(model.terrain, wheel.origin, wheel.rotation.col(1),
                                    model.parameters.geometry.wheel_radius_m) > seen[leg])
      return true;
  }
  return false;
}

void keep_maximum(ContactCounts& seen, const ContactCounts& n) {
  for (int leg = 0; leg < kNumLegs; ++leg) seen[leg] = std::max(seen[leg], n[leg]);
}

bool has_more(const ContactCounts& n, const ContactCounts& seen) {
  for (int leg = 0; leg < kNumLegs; ++leg)
    if (n[leg] > seen[leg]) return true;
  return false;
}

// The state at one time with its right-hand side, keeping the workspace
// (kinematics, contacts, M, F) for the Jacobian and the error control.
struct StepPoint {
  double t = 0.0;
  StateVector x, dx;
  ModelInputs inputs;
  DynamicsWorkspace dynamics;
};

// The time into a step of size h from `start` at which a wheel meets a
// contact region it did not have there (`start_regions`), on the quadratic
// predictor q0 + s u0 + s^2 a0 / 2, u0 + s a0 of the smooth motion before
// the touchdown, by bisection to h / 2^kTouchdownBisections: the last time
// found without the new region, or h if the predictor meets none within h
// (`kinematics` is scratch).
constexpr int kTouchdownBisections = 12;

double predicted_touchdown(const RoverModel& model, const StepPoint& start, const ContactCounts& start_regions,
                           double h, TreeKinematics& kinematics) {
  const Coordinates q0 = start.x.head<kNumCoordinates>(), u0 = start.x.tail<kNumCoordinates>();
  const Coordinates a0 = start.dx.tail<kNumCoordinates>();
  const auto touches = [&](double s) {
    StateVector x;
    x << q0 + s * u0 + (0.5 * s * s) * a0, u0 + s * a0;
    return has_unseen_region(model, x, start_regions, kinematics);
  };
  if (!touches(h)) return h;
  double before = 0.0, after = h;
  for (int i = 0; i < kTouchdownBisections; ++i) {
    const double mid = 0.5 * (before + after);
    (touches(mid) ? after : before) = mid;
  }
  return before;
}

// The right-hand side at a step end, with M (the next step's iteration
// matrix needs it), or at a stage point, where du/dt is all that is needed
// and the articulated-body recursion gives it without forming M.
enum class NeedsMass { kYes, kNo };

void evaluate(const OdeSystem& system, double t, const StateVector& x, StepPoint& point,
              IntegrationReport& report, NeedsMass needs_mass) {
  ++report.rhs_evaluations;
  point.t = t;
  point.x = x;
  point.inputs = system.inputs_at(t);
  point.dx = needs_mass == NeedsMass::kYes ? state_derivative(system.model, point.dynamics, point.inputs, x)
                                          : state_derivative_articulated(system.model, point.dynamics, point.inputs, x);
}

// M0, F0 and the stiff-force Jacobian at an evaluated step start, and the
// frequency at which each coordinate rings on its springs, sqrt(-k_cc / M_cc).
struct Linearization {
  MechanicalLinearization<kNumCoordinates> system;
  Coordinates spring_frequency_radps;
};

// Written into `lin` (every field), which the caller keeps from step to step.
void linearize(const OdeSystem& system, const StepPoint& e, IntegrationReport& report, Linearization& lin) {
  ++report.rhs_evaluations;  // the Jacobian assembly, counted as one evaluation
  Coordinates spring_diagonal;
  stiff_force_jacobian(system.model, e.dynamics, e.inputs, e.x.head<kNumCoordinates>(), e.x.tail<kNumCoordinates>(),
                       lin.system.d_force_d_speed, lin.system.d_force_d_position, spring_diagonal);
  lin.system.mass = e.dynamics.mass_matrix;
  lin.system.force = e.dynamics.forcing;
  lin.spring_frequency_radps =
      ((-spring_diagonal).cwiseMax(0.0).array() / e.dynamics.mass_matrix.diagonal().array()).sqrt().matrix();
}

// Cubic Hermite interpolation between two step ends, at t in [a.t, b.t].
StateVector hermite(const StepPoint& a, const StepPoint& b, double t) {
  const double h = b.t - a.t;
  const double s = (t - a.t) / h;
  const double s2 = s * s, s3 = s2 * s;
  return (2.0 * s3 - 3.0 * s2 + 1.0) * a.x + (h * (s3 - 2.0 * s2 + s)) * a.dx +
         (3.0 * s2 - 2.0 * s3) * b.x + (h * (s3 - s2)) * b.dx;
}

// The absolute tolerance of each state component: atol, except the turning
// rates of the chassis, atol / lever (see the top), the lever taken at the
// start state `kin`.
StateVector absolute_tolerances(const TreeKinematics& kin, const IntegratorSettings& settings) {
  double chassis_lever_m = 0.0;
  for (int leg = 0; leg < kNumLegs; ++leg)
    chassis_lever_m = std::max(chassis_lever_m, (kin.nodes[node::wheel(leg)].origin -
                                                 kin.nodes[node::chassis].origin).norm());
  StateVector tolerance = StateVector::Constant(settings.absolute_tolerance);
  if (chassis_lever_m > 0.0)
    for (const int c : {coord::yaw, coord::pitch, coord::roll})
      tolerance[kNumCoordinates + c] = settings.absolute_tolerance / chassis_lever_m;
  return tolerance;
}

// Tolerance of each state component for a step from x0 to x1 (see the top);
// the spin angle and rate of a wheel touching the ground are left to the slip
// test (infinite tolerance here).
StateVector error_scale(const StateVector& x0, const StateVector& x1, const StateVector& absolute_tolerance,
                        const Coordinates& spring_frequency_radps, const ContactCounts& touching,
                        const IntegratorSettings& settings) {
  constexpr double kLongestActing_s = 1.0;
  StateVector scale = absolute_tolerance.array() +
                      settings.relative_tolerance * x0.cwiseAbs().cwiseMax(x1.cwiseAbs()).array();
  for (int c = 0; c < kNumCoordinates; ++c)
    scale[kNumCoordinates + c] +=
        settings.absolute_tolerance * (std::max(spring_frequency_radps[c] * kLongestActing_s, 1.0) - 1.0);
  for (int leg = 0; leg < kNumLegs; ++leg)
    if (touching[leg] > 0) {
      scale[coord::spin(leg)] = std::numeric_limits<double>::infinity();
      scale[kNumCoordinates + coord::spin(leg)] = std::numeric_limits<double>::infinity();
    }
  return scale;
}

// Row vectors a_j with a_j . u = the absolute angular rate of wheel j about
// its spin axis (the axis component of the angular velocities of every joint
// on the path from the world to the wheel).
using WheelSpinRows = std::array<Eigen::Matrix<double, 1, kNumCoordinates>, kNumLegs>;

WheelSpinRows wheel_spin_rows(const KinematicTree& tree, const TreeKinematics& kinematics) {
  WheelSpinRows rows;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const int wheel = node::wheel(leg);
    rows[leg] = kinematics.nodes[wheel].axis.transpose() * angular_jacobian(tree, kinematics, wheel);
  }
  return rows;
}

// Replaces the error of each wheel's relative spin rate by the error of its
// absolute rate (the top of the file says why).
void measure_wheel_spins(const WheelSpinRows& rows, const Coordinates& speed_error,
                         StateVector& error) {
  for (int leg = 0; leg < kNumLegs; ++leg)
    error[kNumCoordinates + coord::spin(leg)] = rows[leg].dot(speed_error);
}

// Infinite for a step that produced NaN or infinities (rejected, not accepted).
double error_norm(const StateVector& error, const StateVector& scale) {
  if (!error.allFinite()) return std::numeric_limits<double>::infinity();
  const double norm = (error.cwiseAbs().array() / scale.array()).maxCoeff();
  return std::isfinite(norm) ? norm : std::numeric_limits<double>::infinity();
}

// Slip-speed errors at the contacts of the step start. Per unit of slip-speed
// error, the friction force -mu(|v_t|) F_n v_t / |v_t| changes by
// |mu'(|v_t|)| F_n along the slip and turns by mu(|v_t|) / |v_t| across it;
// near stick both are mu'(0), about mu_s / v_s. Its speed scale
//   s(v_t) = mu_s / max(|mu'(|v_t|)|, mu(|v_t|) / |v_t|)
// is the slip-speed change that would change the force by its whole range:
// about v_s near stick, about |v_t| mu_s / mu_k in gross sliding. The error of
// the tangential speed of each contact point, (I - n n^T) J_P e_u, is held to
// slip_tolerance s(v_t) (+ rtol |v_t|): at the default 0.05, stick and the
// Stribeck hump are resolved to 5 % of v_s, a wheel skidding sideways at
// 0.2 m/s to 1 cm/s.

struct SlipRows {
  Eigen::Matrix<double, 3, kNumCoordinates> tangential_jacobian;  // (I - n n^T) J_P
  double slip_speed_mps = 0.0;
  double friction_speed_scale_mps = 0.0;  // s(v_t)
};

// At a pushing contact `c` with slip speed |v_t| = `slip_speed_mps`, mu and
// mu' from the tanh its force evaluation kept (all 0 at zero slip, as
// tanh(0) is).
double friction_speed_scale(const ContactPoint& c, double slip_speed_mps, const FrictionParameters& friction) {
  const double v = std::abs(slip_speed_mps);
  const MakkarTanh& t = c.friction_tanh;
  const double along = std::abs(makkar_mu_derivative(friction.gammas, t));
  const double across = v > 0.0 ? makkar_mu(v, friction.gammas, t) / v : along;
  return friction.mu_static / std::max(along, across);
}

// The rows of every pushing contact of a step start, in a fixed-size array
// (no allocation per step).
struct SlipRowSet {
  std::array<SlipRows, kNumLegs * kMaxContactsPerWheel> rows;
  int count = 0;
};

void slip_rows(const RoverModel& model, const StepPoint& e, SlipRowSet& out) {
  const std::array<WheelContacts, kNumLegs>& contacts = e.dynamics.contacts;
  out.count = 0;
  for (int leg = 0; leg < kNumLegs; ++leg)
    for (int k = 0; k < contacts[leg].count; ++k) {
      const ContactPoint& c = contacts[leg].points[k];
      if (!(c.normal_force_N > 0.0)) continue;
      const Mat3 tangent = Mat3::Identity() - c.normal * c.normal.transpose();
      const double slip = c.slip_velocity_mps.norm();
      out.rows[static_cast<std::size_t>(out.count++)] = {
          tangent * point_jacobian(model.tree, e.dynamics.kinematics, node::wheel(leg), c.point_m), slip,
          friction_speed_scale(c, slip, model.parameters.friction)};
    }
}

double slip_error_norm(const SlipRowSet& slips, const Coordinates& speed_error, const IntegratorSettings& settings) {
  double norm = 0.0;
  for (int i = 0; i < slips.count; ++i) {
    const SlipRows& r = slips.rows[static_cast<std::size_t>(i)];
    norm = std::max(norm, (r.tangential_jacobian * speed_error).norm() /
                              (settings.slip_tolerance * r.friction_speed_scale_mps +
                               settings.relative_tolerance * r.slip_speed_mps));
  }
  return std::isfinite(norm) ? norm : std::numeric_limits<double>::infinity();
}

// The S-structure stiffness in the iteration matrix. A W-method keeps its
// order with any matrix there; for stability it needs the stiffness the step
// meets. At f = 1e5 a joint's torque turns from -M0 to +M0 within 1e-5 rad,
// where its slope 2 M0 f / pi is 1e4 times the slope 1e-3 rad away: a step
// starting off that kink and crossing it would meet the kink's stiffness
// explicitly and be rejected, again and again, until it no longer crossed.
// Each joint instead gets the steepest slope on its path over the step,
// |b - b0| <= h |db0/dt|, i.e. the slope at the point of that range nearest
// to b = 0 (the slope of the start if the range does not come closer).
void stiffen_s_joints_over_step(const RoverParameters& parameters, const ModelInputs& inputs,
                                const Coordinates& q0, const Coordinates& u0, double h,
                                CoordinateMatrix& d_force_d_position) {
  for (int leg = 0; leg < kNumLegs; ++leg)
    for (int i = 0; i < 2; ++i) {
      const int c = coord::s_joint(leg, i);
      const double b = q0[c], reach = h * std::abs(u0[c]);
      const double nearest = std::abs(b) <= reach ? 0.0 : b - std::copysign(reach, b);
      if (nearest == b) continue;
      const auto slope = [&](double angle_rad) {
        return s_structure_stiffness(angle_rad, inputs.preload_Nm[2 * leg + i], inputs.sharpness_f,
                                     parameters.s_structure.stiffness_Nm_per_rad);
      };
      d_force_d_position(c, c) += slope(nearest) - slope(b);
    }
}

// Step-size factor from the error of an order-2 embedded solution (local
// error ~ h^3), with the usual safety factor and bounds. A step accepted
// after its error test rejected a longer one does not grow the next step
// (max_growth 1, as in Hairer and Wanner's RODAS): the next step would
// otherwise reach again into the event that failed the longer one (a contact
// beginning, an S-joint crossing its preload kink), whose error grows far
// faster than h^3, and be rejected again, often several times in a row
// before the event.
// RODAS4's order-3 estimate has local error ~ h^4, hence the fourth root.
double step_factor(double error, double max_growth, int embedded_order) {
  constexpr double kSafety = 0.9, kMinShrink = 0.2;
  if (!(error < std::numeric_limits<double>::infinity())) return kMinShrink;
  if (error <= 0.0) return max_growth;
  const double root = embedded_order == 2 ? std::cbrt(1.0 / error)
                                          : std::pow(1.0 / error, 1.0 / (embedded_order + 1));
  return std::clamp(kSafety * root, kMinShrink, max_growth);
}

// Step control: the largest growth of the step size after an accepted step,
// and the shrinking of a try that missed a contact onset inside it.
constexpr double kMaxGrowth = 5.0, kOnsetShrink = 0.5;
constexpr double kAtTouchdown = 1e-3;  // of a try: a predicted touchdown closer is at its start
constexpr int kTouchdownsInARow = 2;
constexpr std::array<double, 3> kLookInside = {0.25, 0.5, 0.75};  // of an accepted step, for contacts

// What stays fixed for a whole integration.
struct RunSetup {
  const OdeSystem& system;
  const IntegratorSettings& settings;
  bool rodas4 = false;
  int embedded_order = 0;
  double t_end = 0.0;
  // A predicted touchdown is taken only where it is 2^kTouchdownBisections
  // times the shortest step the stall watch lets pass (integrators.hpp), so
  // that the steps after it, down to that fraction of it, pass too.
  double shortest_touchdown = 0.0;
  StateVector absolute_tolerance;  // at the initial state (absolute_tolerances())
};

// The points and the matrices reused from step to step. The two step ends
// trade places after every step (their workspaces are large: swapping
// pointers, not contents), so the workspace is not copied.
struct Workspace {
  std::array<StepPoint, 2> ends;
  StepPoint* start = &ends[0];
  StepPoint* end = &ends[1];
  StepPoint stage;
  BranchInducedLU iteration;  // of M0 - h g D - h^2 g^2 K
  Linearization lin;
  Workspace() = default;
  Workspace(const Workspace&) = delete;
  Workspace& operator=(const Workspace&) = delete;
};

// What the evaluated start of a step fixes for every try of the step.
struct StepStart {
  // K's diagonal at the step start; each try stiffens its S-joint entries
  // over its own h (stiffen_s_joints_over_step), from this.
  Coordinates stiffness;
  Coordinates q0, u0;
  ContactCounts contacts, regions;
  SlipRowSet slips;
  WheelSpinRows spins;
};

// The tries of one step: the size of the next try, what the last one found,
// and how the step has gone so far.
struct StepTries {
  double h = 0.0;
  double error = 0.0, t1 = 0.0;  // of the last try, and its end once accepted
  bool rejected = false;         // by the error test, at a longer step
  // Whether the try under way ends at a predicted touchdown, and whether
  // one has been tried in this step: at most one, and none after
  // kTouchdownsInARow steps that ended at one (each lands up to
  // 2^kTouchdownBisections times closer to it; the step across it is left
  // to the error estimate).
  bool located = false, touchdown_tried = false;
};

// One try's result: the end state, its error norm, and the contacts
// (pushing) and contact regions seen at the start and the stages.
struct TryResult {
  StateVector x1;
  double error = 0.0;
  ContactCounts seen, seen_regions;
};

// Fills the report's status for a step size below min_step (`why` names the
// cause) and returns false, so that the caller stops.
bool fail_underflow(IntegrationReport& report, const IntegratorSettings& settings, double t, double h,
                    const std::string& why) {
  report.status = SimulationStatus::kStepSizeUnderflow;
  report.failed_at_s = t;
  report.detail = "step " + number_text(h) + " s is below min_step " +
                  number_text(settings.min_step_s) + " s (" + why + ")";
  return false;
}

// Linearizes at the evaluated step start and gathers what every try of the
// step needs from it (written into `out`, every field).
void prepare_step_start(const RunSetup& run, Workspace& ws, IntegrationReport& report, StepStart& out) {
  linearize(run.system, *ws.start, report, ws.lin);
  out.stiffness = ws.lin.system.d_force_d_position.diagonal();
  out.q0 = ws.start->x.head<kNumCoordinates>();
  out.u0 = ws.start->x.tail<kNumCoordinates>();
  out.contacts = active_contacts(ws.start->dynamics.contacts);
  out.regions = contact_regions(ws.start->dynamics.contacts);
  slip_rows(run.system.model, *ws.start, out.slips);
  out.spins = wheel_spin_rows(run.system.model.tree, ws.start->dynamics.kinematics);
}

// One try of size h from the step start: the S-joint stiffening over h, the
// LU of the iteration matrix, the Rosenbrock stages (each counted as a
// right-hand side, its contacts kept in `seen` and `seen_regions`), and the
// error norm of the embedded solution (infinite for a non-finite end state).
TryResult try_step(const RunSetup& run, const StepStart& s, Workspace& ws, IntegrationReport& report, double h) {
  TryResult out;
  out.seen = s.contacts;
  out.seen_regions = s.regions;
  auto acceleration = [&](double t, const Coordinates& q, const Coordinates& u) -> Coordinates {
    StateVector x;
    x << q, u;
    evaluate(run.system, t, x, ws.stage, report, NeedsMass::kNo);
    keep_maximum(out.seen, active_contacts(ws.stage.dynamics.contacts));
    keep_maximum(out.seen_regions, contact_regions(ws.stage.dynamics.contacts));
    return ws.stage.dx.tail<kNumCoordinates>();
  };
  MechanicalLinearization<kNumCoordinates>& lin = ws.lin.system;
  lin.d_force_d_position.diagonal() = s.stiffness;
  stiffen_s_joints_over_step(run.system.model.parameters, ws.start->inputs, s.q0, s.u0, h, lin.d_force_d_position);
  ws.iteration.compute(run.rodas4 ? rosenbrock_iteration_matrix(lin, h, kRodas4.gamma)
                                  : ros34pw2_iteration_matrix(lin, h));
  const double t0 = ws.start->t;
  const RosenbrockWStep<kNumCoordinates> step =
      run.rodas4 ? rosenbrock_step(kRodas4, lin, ws.iteration, t0, s.q0, s.u0, h, acceleration)
                 : ros34pw2_step<kNumCoordinates>(lin, ws.iteration, t0, s.q0, s.u0, h, acceleration);
  StateVector e;
  out.x1 << step.q, step.u;
  e << step.error_q, step.error_u;
  measure_wheel_spins(s.spins, step.error_u, e);
  out.error = !out.x1.allFinite()
                  ? std::numeric_limits<double>::infinity()
                  : std::max(error_norm(e, error_scale(ws.start->x, out.x1, run.absolute_tolerance,
                                                      ws.lin.spring_frequency_radps, s.contacts, run.settings)),
                             slip_error_norm(s.slips, step.error_u, run.settings));
  return out;
}

// Evaluates the end t1 of a try that passed the error test (into ws.end) and
// returns whether the try missed a contact onset: a pushing contact at the
// end that no stage had, or a contact region on the cubic Hermite output
// inside the step (at kLookInside) that no evaluated point had.
bool misses_contact_onset(const RunSetup& run, Workspace& ws, IntegrationReport& report, TryResult& tried,
                          double t1) {
  evaluate(run.system, t1, tried.x1, *ws.end, report, NeedsMass::kYes);
  keep_maximum(tried.seen_regions, contact_regions(ws.end->dynamics.contacts));
  bool missed = has_more(active_contacts(ws.end->dynamics.contacts), tried.seen);
  for (const double s : kLookInside) {
    // Nothing to interpolate for once every wheel has its most regions.
    if (missed || every_wheel_has_most_regions(run.system.model, tried.seen_regions)) break;
    const StateVector inside = hermite(*ws.start, *ws.end, ws.start->t + s * (t1 - ws.start->t));
    missed = has_unseen_region(run.system.model, inside, tried.seen_regions, ws.stage.dynamics.kinematics);
  }
  return missed;
}

// After a try that failed the error test: the size of the next try, at a
// predicted touchdown if a stage met a contact region that the start did not
// have, else shrunk by the error. False (report filled in) on underflow.
bool shrink_after_error(const RunSetup& run, const StepStart& s, Workspace& ws, const TryResult& tried,
                        StepTries& tries, IntegrationReport& report) {
  tries.rejected = true;
  ++report.rejected_steps;
  tries.located = false;
  // A stage met a contact that the start did not have: once per step,
  // the next try ends where the smooth motion before it meets it, unless
  // the step starts there already (the error estimate then shrinks it).
  if (!tries.touchdown_tried && has_more(tried.seen_regions, s.regions)) {
    const double touchdown =
        predicted_touchdown(run.system.model, *ws.start, s.regions, tries.h, ws.stage.dynamics.kinematics);
    if (touchdown < tries.h && touchdown > std::max(kAtTouchdown * tries.h, run.shortest_touchdown)) {
      tries.touchdown_tried = tries.located = true;
      tries.h = touchdown;
      return true;
    }
  }
  tries.h *= step_factor(tries.error, 1.0, run.embedded_order);
  if (tries.h < run.settings.min_step_s)
    return fail_underflow(report, run.settings, ws.start->t, tries.h, "error estimate " + number_text(tries.error));
  return true;
}

// Tries steps from the step start until one passes the error test and misses
// no touchdown; its end is then in ws.end at tries.t1. False (report filled
// in) if the step size fell below min_step.
bool try_until_accepted(const RunSetup& run, const StepStart& s, Workspace& ws, StepTries& tries,
                        IntegrationReport& report) {
  for (;;) {
    bool last = false;
    if (ws.start->t + tries.h >= run.t_end * (1.0 - 1e-15)) {
      tries.h = run.t_end - ws.start->t;
      last = true;
    }
    TryResult tried = try_step(run, s, ws, report, tries.h);
    tries.error = tried.error;
    if (!(tries.error <= 1.0)) {
      if (!shrink_after_error(run, s, ws, tried, tries, report)) return false;
      continue;
    }
    tries.t1 = last ? run.t_end : ws.start->t + tries.h;
    if (!misses_contact_onset(run, ws, report, tried, tries.t1)) return true;
    ++report.rejected_steps;
    tries.located = false;
    tries.h *= kOnsetShrink;  // a touchdown inside the step that no stage saw
    if (tries.h < run.settings.min_step_s)
      return fail_underflow(report, run.settings, ws.start->t, tries.h, "touchdown");
  }
}

// Records the samples that fall within the accepted step from ws.start to
// ws.end (from sample `next` on, advanced past them), the one at the step
// end exactly and the others on the cubic Hermite output.
void record_samples(const IntegrationRequest& request, const Workspace& ws, std::size_t& next) {
  const double t1 = ws.end->t;
  for (; next < request.sample_count; ++next) {
    const double ts = static_cast<double>(next) * request.sample_period_s;
    if (!(ts <= t1)) break;
    request.record(ts, ts >= t1 ? ws.end->x : hermite(*ws.start, *ws.end, ts));
  }
}

}  // namespace

// The integration loop: per step, the linearization at its start, the tries
// until one is accepted, the bookkeeping and stall watch of step_is_bad(),
// the samples within it, and the size of the next step.
IntegrationReport integrate_rosenbrock(const OdeSystem& system, StateVector x,
                                       const IntegratorSettings& settings,
                                       const IntegrationRequest& request) {
  IntegrationReport report;
  request.record(0.0, x);
  if (request.sample_count < 2) return report;
  const bool rodas4 = settings.method == IntegratorMethod::kRodas4;
  const double t_end = static_cast<double>(request.sample_count - 1) * request.sample_period_s;
  Workspace ws;
  evaluate(system, 0.0, x, *ws.start, report, NeedsMass::kYes);
  const RunSetup run{system,
                     settings,
                     rodas4,
                     rodas4 ? kRodas4.embedded_order : kRos34pw2.embedded_order,
                     t_end,
                     std::ldexp(StallWatch::kRoundingUnits, kTouchdownBisections) *
                         std::numeric_limits<double>::epsilon() * t_end,
                     absolute_tolerances(ws.start->dynamics.kinematics, settings)};
  StallWatch stall;
  StepStart step_start;
  double h = std::clamp(settings.initial_step_s, settings.min_step_s, settings.max_step_s);
  std::size_t next = 1;
  int touchdowns_in_a_row = 0;  // steps that ended at a predicted touchdown, the last ones
  while (next < request.sample_count) {
    prepare_step_start(run, ws, report, step_start);
    StepTries tries;
    tries.h = h;
    tries.touchdown_tried = touchdowns_in_a_row >= kTouchdownsInARow;
    if (!try_until_accepted(run, step_start, ws, tries, report)) return report;
    touchdowns_in_a_row = tries.located ? touchdowns_in_a_row + 1 : 0;
    const double taken = tries.t1 - ws.start->t;
    if (step_is_bad(report, stall, tries.t1, taken, ws.end->x, request)) return report;
    record_samples(request, ws, next);
    std::swap(ws.start, ws.end);
    if (request.progress) request.progress(tries.t1);
    h = std::min(taken * step_factor(tries.error, tries.rejected ? 1.0 : kMaxGrowth, run.embedded_order),
                 settings.max_step_s);
  }
  return report;
}

}  // namespace rover
