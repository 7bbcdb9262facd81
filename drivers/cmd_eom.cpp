// `rover eom`: prints the equations of motion M(q), F(q, u) at one state, with
// the world positions of B_l, B_r, G and the wheel centres and the contacts.
// A state at which any printed number is not finite (NaN or an overflow) is
// an error naming the quantity, not JSON null.
#include <cmath>
#include <iostream>

#include "core/equations_of_motion.hpp"
#include "drivers/command_registry.hpp"
#include "drivers/options.hpp"
#include "io/json_reader.hpp"
#include "io/model_config.hpp"
#include "io/scenario_config.hpp"

namespace rover::cli {
namespace {

io::Json vec_json(const Eigen::Ref<const Eigen::VectorXd>& v) {
  io::Json a = io::Json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(v[i]);
  return a;
}

Coordinates read_coordinates(const io::JsonReader& r, const std::string& key) {
  const auto values = r.fixed_numbers<kNumCoordinates>(key);
  return Eigen::Map<const Coordinates>(values.data());
}

// A state within the rover's scale (core/model_scale.hpp), as a scenario's
// initial state and references are: the position of G, the speeds and the
// wheel speed and steering references.
void check_state_scale(const io::JsonReader& state, const RoverModel& model, const Coordinates& q,
                       const Coordinates& u, const ModelInputs& inputs) {
  for (const int index : {coord::x, coord::y, coord::z})
    if (const std::string p = beyond_scale(q[index], kMaxCoordinate_m, "m", kPositionScaleReason); !p.empty())
      state.fail("q", "entry " + std::to_string(index) + " (" + kCoordinateNames[index] + ") = " + p);
  const io::SpeedScale scale = io::speed_scale(model);
  const double radius = scale.wheel_radius_m;
  for (int index = 0; index < kNumCoordinates; ++index)
    if (const std::string p = io::speed_beyond_scale(index, u[index], scale); !p.empty())
      state.fail("u", "entry " + std::to_string(index) + " (" + kCoordinateNames[index] + ") = " + p);
  if (const std::string problem = io::pose_angle_problem(model, q); !problem.empty()) state.fail("q", problem);
  // The contact law models a rim pressed into the ground; a wheel deeper than
  // its own radius is buried, and its forces mean nothing.
  if (const io::WheelPenetration deepest = io::deepest_wheel_penetration(model, q);
      deepest.depth_m > model.parameters.geometry.wheel_radius_m)
    state.fail("q", std::string("wheel ") + kWheelNames[static_cast<std::size_t>(deepest.leg)] + " is " +
                        number_text(deepest.depth_m) + " m deep in the ground, more than its radius " +
                        number_text(model.parameters.geometry.wheel_radius_m) +
                        " m: the contact law holds for a rim pressed into the ground, not a buried wheel; "
                        "raise q[2] (z)");
  if (!state.has("params")) return;
  const io::JsonReader params = state.child("params");
  const double limit = model.parameters.steering.limit_rad;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    if (const std::string p = io::rate_beyond_scale(inputs.wheel_speed_ref_radps[leg], radius); !p.empty())
      params.fail("w_ref", "element " + std::to_string(leg) + ": " + p);
    if (!(std::abs(inputs.steer_ref_rad[leg]) <= limit))
      params.fail("d_ref", "element " + std::to_string(leg) + " (" + number_text(inputs.steer_ref_rad[leg]) +
                               " rad) is beyond the steering end-stop +-" + number_text(limit) + " rad");
  }
}

struct EomOptions {
  std::string config = kDefaultRoverConfig;
  std::string terrain;
  std::string state;
  CLI::Option* config_option = nullptr;
};

int run_eom(const EomOptions& o) {
  const RoverModel model =
      io::load_rover_model(path_option(o.config_option, o.config, kDefaultRoverConfig), o.terrain);
  const io::Json state_json = io::read_json_file(o.state);
  const io::JsonReader state(state_json, o.state);
  const Coordinates q = read_coordinates(state, "q");
  const Coordinates u = read_coordinates(state, "u");
  ModelInputs inputs = nominal_inputs(model.parameters);
  if (state.has("params")) inputs = io::parse_model_inputs(state.child("params"), inputs);
  state.finish();
  check_state_scale(state, model, q, u, inputs);

  DynamicsWorkspace eom;
  compute_dynamics(model, eom, inputs, q, u);
  const TreeKinematics& kin = eom.kinematics;

  io::Json out;
  out["M"] = io::Json::array();
  for (int r = 0; r < kNumCoordinates; ++r) out["M"].push_back(vec_json(eom.mass_matrix.row(r).transpose()));
  out["F"] = vec_json(eom.forcing);
  out["F_nocontact"] = vec_json(eom.forcing_without_contact);
  out["points"]["B_l"] = vec_json(kin.nodes[node::bogie_left].origin);
  out["points"]["B_r"] = vec_json(kin.nodes[node::bogie_right].origin);
  out["points"]["G"] = vec_json(kin.nodes[node::chassis].origin);
  out["points"]["wheel_centres"] = io::Json::array();
  out["contacts"] = io::Json::array();
  for (int leg = 0; leg < kNumLegs; ++leg) {
    out["points"]["wheel_centres"].push_back(vec_json(kin.nodes[node::wheel(leg)].origin));
    io::Json wheel = io::Json::array();
    for (int k = 0; k < eom.contacts[leg].count; ++k) {
      const ContactPoint& c = eom.contacts[leg].points[k];
      wheel.push_back({{"point", vec_json(c.point_m)},
                       {"normal", vec_json(c.normal)},
                       {"penetration", c.penetration_m},
                       {"Fn", c.normal_force_N},
                       {"Ft", vec_json(c.friction_force_N)}});
    }
    out["contacts"].push_back(wheel);
  }
  require_finite_output(out, "at the state of '" + o.state + "' (fields q and u: an entry far beyond the rover's "
                             "scale, metres and radians per second, overflows the forces)");
  std::cout << out.dump() << "\n";
  return 0;
}

const RegisterCommand eom_command{
    10, "eom", "Print the equations of motion M(q) du/dt = F(q, u) at one state, as JSON",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<EomOptions>();
      app.footer(
          "STATE.json: {\"q\": [23 numbers], \"u\": [23 numbers], optional \"params\": {\"f\": .., "
          "\"c_q\": .., \"M0\": [8], \"w_ref\": [4], \"d_ref\": [4]}}; coordinates in the order of "
          "docs/model.md §2 (x y z theta chi psi phi b11 b12 b21 b22 b31 b32 b41 b42 d1..d4 "
          "z1..z4).\nOutput: {\"M\": [[23x23]], \"F\": [23], \"F_nocontact\": [23], \"points\": "
          "{\"B_l\", \"B_r\", \"G\", \"wheel_centres\"}, \"contacts\": [per wheel: [{point, normal, "
          "penetration, Fn, Ft}]]}.\n\nExample:\n  rover eom --state state.json --terrain "
          "configs/terrains/obstacle.json");
      o->config_option = app.add_option("--config", o->config,
                                        "Rover parameters (JSON); by default configs/rover.json "
                                        "of the working directory, else of this program's repository")
                             ->capture_default_str()
                             ->check(CLI::ExistingFile);
      app.add_option("--terrain", o->terrain, "Terrain file (JSON); default: flat ground z = 0")->check(CLI::ExistingFile);
      app.add_option("--state", o->state, "State file (JSON), see below")->required()->check(CLI::ExistingFile);
      return [o] { return run_eom(*o); };
    }};

}  // namespace
}  // namespace rover::cli
