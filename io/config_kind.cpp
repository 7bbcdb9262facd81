// See config_kind.hpp.
#include "io/config_kind.hpp"

#include <algorithm>
#include <cctype>
#include <string_view>

namespace rover::io {
namespace {

// What to give instead, by the kind a command wanted.
std::string advice(ConfigKind wanted) {
  switch (wanted) {
    case ConfigKind::kRover: return "give a rover file (configs/rover.json), which a scenario's \"rover\" names";
    case ConfigKind::kScenario:
      return "give a scenario file (configs/scenarios/), such as the one a study's \"scenario\" names";
    case ConfigKind::kStudy: return "give a study file (configs/studies/), whose \"scenario\" names a scenario file";
    case ConfigKind::kTerrain: return "give a terrain file (configs/terrains/), which a scenario's \"terrain\" names";
    case ConfigKind::kCandidates:
      return "give a candidates file (configs/experiments/), a \"candidates\" list of experiments";
    case ConfigKind::kUnknown: break;
  }
  return "give a JSON config";
}

// The key that tells `kind`, and how the message describes it.
struct KindMark {
  std::string key;
  std::string what;
};

KindMark mark(ConfigKind kind) {
  switch (kind) {
    case ConfigKind::kRover: return {"bodies", "a rover file (its bodies)"};
    case ConfigKind::kScenario: return {"rover", "a scenario file (it names its rover file here)"};
    case ConfigKind::kStudy: return {"type", "a study file (a study's \"type\")"};
    case ConfigKind::kTerrain: return {"type", "a terrain file (a terrain's \"type\")"};
    case ConfigKind::kCandidates: return {"candidates", "a candidates file of rover calibrate --next-experiment"};
    case ConfigKind::kUnknown: break;
  }
  return {"", ""};
}

bool ends_with_csv(const std::string& path) {
  if (path.size() < 4) return false;
  std::string tail = path.substr(path.size() - 4);
  std::transform(tail.begin(), tail.end(), tail.begin(), [](unsigned char c) { return std::tolower(c); });
  return tail == ".csv";
}

// The first character that is not white space, or '\0'.
char first_visible(std::string_view text) {
  const auto it = std::find_if(text.begin(), text.end(), [](unsigned char c) { return !std::isspace(c); });
  return it == text.end() ? '\0' : *it;
}

}  // namespace

ConfigKind config_kind(const Json& config) {
  if (!config.is_object()) return ConfigKind::kUnknown;
  if (config.contains("bodies")) return ConfigKind::kRover;
  if (config.contains("rover")) return ConfigKind::kScenario;
  if (config.contains("candidates")) return ConfigKind::kCandidates;
  if (!config.contains("type")) return ConfigKind::kUnknown;
  const Json& type = config.at("type");
  const bool terrain_type = type == "flat" || type == "grid" || type == "control_points";
  if (config.contains("scenario") || config.contains("model") || config.contains("design")) return ConfigKind::kStudy;
  return terrain_type ? ConfigKind::kTerrain : ConfigKind::kUnknown;
}

std::string config_kind_name(ConfigKind kind) {
  switch (kind) {
    case ConfigKind::kRover: return "rover file";
    case ConfigKind::kScenario: return "scenario file";
    case ConfigKind::kStudy: return "study file";
    case ConfigKind::kTerrain: return "terrain file";
    case ConfigKind::kCandidates: return "candidates file";
    case ConfigKind::kUnknown: break;
  }
  return "config file";
}

void refuse_other_config_kind(const Json& config, const std::string& file, ConfigKind wanted) {
  const ConfigKind kind = config_kind(config);
  if (kind == ConfigKind::kUnknown || kind == wanted) return;
  const KindMark found = mark(kind);
  JsonReader(config, file).fail(found.key, "this is " + found.what + ", not a " + config_kind_name(wanted) + ": " +
                                               advice(wanted));
}

Json read_config_file(const std::string& path, ConfigKind wanted) {
  const std::string text = read_json_text(path);
  const char first = first_visible(text);
  if (first == '#' || (ends_with_csv(path) && first != '{' && first != '\0'))
    throw ConfigError(path + ": a CSV (text data) file" +
                      (first == '#' ? std::string(" (its first line is a '#' comment)") : std::string()) +
                      ", not a JSON " + config_kind_name(wanted) + ": " + advice(wanted));
  Json config = parse_json_text(text, path);
  refuse_other_config_kind(config, path, wanted);
  return config;
}

}  // namespace rover::io
