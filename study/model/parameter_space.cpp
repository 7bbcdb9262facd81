// See parameter_space.hpp.
#include "study/model/parameter_space.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "core/coordinates.hpp"
#include "core/rover_parameters.hpp"
#include "io/nearest_name.hpp"

namespace rover::study {
namespace {

constexpr const char* kScenarioPrefix = "scenario.";
// The common factor of the eight preloads (alias "M0_scale"): not a number of
// the rover file but a parameter of the space, nominal 1.
constexpr const char* kPreloadScale = "s_structure.preload_scale";
constexpr const char* kPreloadMean = "s_structure.preload_mean";

// The spread of the "M0": {"from_config": true} draws, which no run reads.
constexpr const char* kPreloadSpread = "s_structure.preload_sd";

// Rover keys that are derived, labels or the spread of a draw, not parameters.
bool excluded_rover_key(const std::string& path) {
  for (const char* key : {"friction.gammas", "friction.gammas_fitted_to", "s_structure.preload_order", kPreloadSpread}) {
    const std::string k = key;
    if (path == k || path.rfind(k + "[", 0) == 0) return true;
  }
  return false;
}

// Scenario keys a study may set even when the scenario file leaves them out.
// Keys that change the output grid (duration, output_rate) are not parameters.
const std::vector<std::string>& optional_scenario_keys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> k{"forward_speed", "initial_ground_clearance", "wall_time_budget"};
    for (const char* c : kCoordinateNames) {
      k.push_back(std::string("initial_q.") + c);
      k.push_back(std::string("initial_u.") + c);
    }
    return k;
  }();
  return keys;
}

// Keys that set the runs' common time grid (every run of a study is recorded
// on one: the duration, or the travel distance that gives it).
bool time_grid_key(const std::string& path) {
  return path == "duration" || path == "output_rate" || path == "travel_distance";
}

bool excluded_scenario_key(const std::string& path) {
  return time_grid_key(path) || path.rfind("integrator", 0) == 0 || path.rfind("inputs", 0) == 0 ||
         path.rfind("drive", 0) == 0;
}

// Every number in a JSON tree, as dotted paths with [i] for array elements.
void collect_numbers(const io::Json& node, const std::string& path, std::vector<std::string>& out) {
  if (node.is_number()) {
    out.push_back(path);
  } else if (node.is_object()) {
    for (const auto& [key, value] : node.items())
      collect_numbers(value, path.empty() ? key : path + "." + key, out);
  } else if (node.is_array()) {
    for (std::size_t i = 0; i < node.size(); ++i)
      collect_numbers(node[i], path + "[" + std::to_string(i) + "]", out);
  }
}

// One step of a dotted path: a key, then any number of [i].
struct PathStep {
  std::string key;
  std::vector<std::size_t> indices;
};

std::vector<PathStep> split_path(const std::string& path) {
  std::vector<PathStep> steps;
  std::size_t start = 0;
  while (start <= path.size()) {
    const std::size_t dot = path.find('.', start);
    const std::string part = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    PathStep step;
    const std::size_t bracket = part.find('[');
    step.key = part.substr(0, bracket);
    for (std::size_t b = bracket; b != std::string::npos; b = part.find('[', b + 1)) {
      const std::size_t close = part.find(']', b);
      step.indices.push_back(std::stoul(part.substr(b + 1, close - b - 1)));
    }
    steps.push_back(std::move(step));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return steps;
}

// The node at `path`, created (as objects) if `create`; nullptr if absent.
const io::Json* find(const io::Json& root, const std::string& path) {
  const io::Json* node = &root;
  for (const PathStep& step : split_path(path)) {
    if (!node->is_object() || !node->contains(step.key)) return nullptr;
    node = &(*node)[step.key];
    for (std::size_t i : step.indices) {
      if (!node->is_array() || i >= node->size()) return nullptr;
      node = &(*node)[i];
    }
  }
  return node;
}

io::Json& find_or_create(io::Json& root, const std::string& path) {
  io::Json* node = &root;
  for (const PathStep& step : split_path(path)) {
    node = &(*node)[step.key];
    for (std::size_t i : step.indices) node = &node->at(i);
  }
  return *node;
}

// Where a rover name is shadowed by the scenario's "inputs" block.
std::string scenario_inputs_path(const std::string& rover_name) {
  if (rover_name == "s_structure.f") return "inputs.f";
  if (rover_name == "s_structure.c_q") return "inputs.c_q";
  const std::string preload = "s_structure.preload_mean";
  if (rover_name.rfind(preload, 0) == 0) return "inputs.M0" + rover_name.substr(preload.size());
  return "";
}

std::map<std::string, std::string> alias_table() {
  std::map<std::string, std::string> table{
      {"f", "s_structure.f"}, {"c_q", "s_structure.c_q"}, {"M0_scale", kPreloadScale}};
  for (int i = 0; i < kNumSJoints; ++i) {
    const std::string target = "s_structure.preload_mean[" + std::to_string(i) + "]";
    table[preload_alias(i)] = target;
    table["s_structure." + preload_alias(i)] = target;
  }
  return table;
}

}  // namespace

std::string preload_alias(int index) {
  return "M0_" + std::to_string(index / 2 + 1) + std::to_string(index % 2 + 1);
}

namespace {

// The preload index 0..7 of a canonical name, or -1.
int preload_index_of(const std::string& canonical_name) {
  for (int i = 0; i < kNumSJoints; ++i)
    if (canonical_name == std::string(kPreloadMean) + "[" + std::to_string(i) + "]") return i;
  return -1;
}

}  // namespace

std::string run_setting_not_parameter(const std::string& canonical_name) {
  if (canonical_name != "scenario.wall_time_budget") return "";
  return "is the runs' wall-time limit, a setting of the computation and no property of the rover or the drop: "
         "varying it varies no physics (only which runs are cut short), and no data can tell its value";
}

bool parameters_overlap(const std::string& a, const std::string& b) {
  if (a == b) return true;
  return (a == kPreloadScale && preload_index_of(b) >= 0) || (b == kPreloadScale && preload_index_of(a) >= 0);
}

std::string overlap_reason(const std::string& a, const std::string& b) {
  if (a == b || !parameters_overlap(a, b)) return "";
  const std::string preload = a == kPreloadScale ? b : a;
  return "M0_scale (" + std::string(kPreloadScale) + ") multiplies all eight preloads, " +
         preload_alias(preload_index_of(preload)) + " (" + preload + ") among them, so the run would depend on "
         "the order the two are applied in; vary the preloads one by one, or all of them by M0_scale, not both";
}

ParameterSpace::ParameterSpace(const io::Json& rover, const io::Json& scenario)
    : rover_(&rover), scenario_(&scenario) {
  std::vector<std::string> rover_names, scenario_names;
  collect_numbers(rover, "", rover_names);
  collect_numbers(scenario, "", scenario_names);
  for (const std::string& n : rover_names)
    if (!excluded_rover_key(n)) names_.push_back(n);
  for (const std::string& n : scenario_names)
    if (!excluded_scenario_key(n)) names_.push_back(kScenarioPrefix + n);
  for (const std::string& n : optional_scenario_keys()) names_.push_back(kScenarioPrefix + n);
  if (find(rover, kPreloadMean) != nullptr) names_.push_back(kPreloadScale);
  std::sort(names_.begin(), names_.end());
  names_.erase(std::unique(names_.begin(), names_.end()), names_.end());
}

std::vector<std::string> ParameterSpace::aliases() const {
  std::vector<std::string> out;
  for (const auto& [alias, target] : alias_table()) out.push_back(alias);
  return out;
}

bool ParameterSpace::contains(const std::string& name) const {
  const auto table = alias_table();
  const std::string target = table.count(name) ? table.at(name) : name;
  return std::binary_search(names_.begin(), names_.end(), target);
}

std::string ParameterSpace::canonical(const std::string& name) const {
  const auto table = alias_table();
  const std::string target = table.count(name) ? table.at(name) : name;
  if (target == std::string(kScenarioPrefix) + "forward_speed" && scenario_->contains("travel_distance"))
    throw std::invalid_argument("parameter '" + name + "' sets the length of the runs of a scenario that gives "
                                "travel_distance (duration = travel_distance / forward_speed), which cannot vary "
                                "from run to run (every run is recorded on its scenario's one time grid): give "
                                "the scenario a duration instead, or run one study per value");
  if (std::binary_search(names_.begin(), names_.end(), target)) return target;
  if (target.rfind(kPreloadSpread, 0) == 0)
    throw std::invalid_argument("parameter '" + name + "' is no input of a run: the rover file's preload_sd is the "
                                "spread of the preloads drawn by \"M0\": {\"distribution\": \"normal\", "
                                "\"from_config\": true}, and a run reads only the preloads themselves; vary the "
                                "preloads (M0, M0_11 ... M0_42, M0_scale) instead");
  if (target.rfind(kScenarioPrefix, 0) == 0 && time_grid_key(target.substr(std::string(kScenarioPrefix).size())))
    throw std::invalid_argument("parameter '" + name + "' sets the length or output rate of the runs, which "
                                "cannot vary from run to run (every run is recorded on its scenario's one time "
                                "grid): set it in the scenario file, or run one study per value");
  std::vector<std::string> all = names_;
  for (const auto& [alias, t] : table) all.push_back(alias);
  std::sort(all.begin(), all.end(), [&](const std::string& a, const std::string& b) {
    return io::edit_distance(name, a) < io::edit_distance(name, b);
  });
  std::string message = "unknown parameter '" + name + "'; did you mean '" + all[0] + "'";
  if (all.size() > 1) message += " or '" + all[1] + "'";
  message += "? Valid names: the numbers of the rover file by dotted path (";
  for (std::size_t i = 0; i < names_.size(); ++i) {
    if (names_[i].rfind(kScenarioPrefix, 0) == 0) continue;
    message += (i ? ", " : "") + names_[i];
  }
  message += "), of the scenario prefixed 'scenario.' (";
  bool first = true;
  for (const std::string& n : names_)
    if (n.rfind(kScenarioPrefix, 0) == 0) {
      message += (first ? "" : ", ") + n;
      first = false;
    }
  message += "), and the aliases f, c_q, M0_11 ... M0_42, M0_scale";
  throw std::invalid_argument(message);
}

double ParameterSpace::nominal(const std::string& name) const {
  if (name == kPreloadScale) return 1.0;
  const io::Json* node = nullptr;
  if (name.rfind(kScenarioPrefix, 0) == 0) {
    node = find(*scenario_, name.substr(std::string(kScenarioPrefix).size()));
  } else {
    const std::string shadow = scenario_inputs_path(name);
    if (!shadow.empty()) node = find(*scenario_, shadow);
    if (node == nullptr) node = find(*rover_, name);
  }
  return node != nullptr && node->is_number() ? node->get<double>() : std::nan("");
}

void ParameterSpace::apply(const std::string& name, double value, io::Json& rover,
                           io::Json& scenario) const {
  if (name == kPreloadScale) {  // every preload, as the documents hold it now, times value
    for (int i = 0; i < kNumSJoints; ++i) {
      const std::string preload = std::string(kPreloadMean) + "[" + std::to_string(i) + "]";
      io::Json& m = find_or_create(rover, preload);
      m = m.get<double>() * value;
      const std::string shadow = scenario_inputs_path(preload);
      if (const io::Json* node = find(scenario, shadow); node != nullptr && node->is_number())
        find_or_create(scenario, shadow) = node->get<double>() * value;
    }
    return;
  }
  if (name.rfind(kScenarioPrefix, 0) == 0) {
    find_or_create(scenario, name.substr(std::string(kScenarioPrefix).size())) = value;
    return;
  }
  find_or_create(rover, name) = value;
  const std::string shadow = scenario_inputs_path(name);
  if (!shadow.empty() && find(scenario, shadow) != nullptr) find_or_create(scenario, shadow) = value;
}

}  // namespace rover::study
