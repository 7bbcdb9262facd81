// See json_reader.hpp.
#include "io/json_reader.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

namespace rover::io {

Json read_json_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ": cannot open file");
  try {
    return Json::parse(in, nullptr, true, /*ignore_comments=*/true);
  } catch (const Json::parse_error& e) {
    throw ConfigError(path + ": invalid JSON: " + e.what());
  }
}

JsonReader::JsonReader(const Json& object, std::string file, std::string path)
    : object_(object), file_(std::move(file)), path_(std::move(path)) {
  if (!object_.is_object())
    throw ConfigError(file_ + ": field '" + (path_.empty() ? "<top level>" : path_) +
                      "': expected a JSON object, got " + object_.dump());
}

std::string JsonReader::field(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

void JsonReader::fail(const std::string& key, const std::string& problem) const {
  std::string value;
  if (object_.contains(key)) {
    value = object_.at(key).dump();
    if (value.size() > 80) value = value.substr(0, 77) + "...";
    value = " (value " + value + ")";
  }
  throw ConfigError(file_ + ": field '" + field(key) + "'" + value + ": " + problem);
}

bool JsonReader::has(const std::string& key) const {
  used_.insert(key);
  return object_.contains(key);
}

const Json& JsonReader::raw(const std::string& key) const {
  used_.insert(key);
  if (!object_.contains(key)) fail(key, "missing required field");
  return object_.at(key);
}

double JsonReader::number(const std::string& key) const {
  const Json& v = raw(key);
  if (!v.is_number()) fail(key, "expected a number");
  const double x = v.get<double>();
  if (!std::isfinite(x)) fail(key, "expected a finite number");
  return x;
}

int JsonReader::integer(const std::string& key) const {
  const Json& v = raw(key);
  if (!v.is_number_integer()) fail(key, "expected an integer");
  return v.get<int>();
}

std::string JsonReader::string(const std::string& key) const {
  const Json& v = raw(key);
  if (!v.is_string()) fail(key, "expected a string");
  return v.get<std::string>();
}

bool JsonReader::boolean(const std::string& key) const {
  const Json& v = raw(key);
  if (!v.is_boolean()) fail(key, "expected true or false");
  return v.get<bool>();
}

std::vector<double> JsonReader::numbers(const std::string& key) const {
  const Json& v = raw(key);
  if (!v.is_array()) fail(key, "expected an array of numbers");
  std::vector<double> out;
  out.reserve(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!v[i].is_number() || !std::isfinite(v[i].get<double>()))
      fail(key, "element " + std::to_string(i) + " is not a finite number");
    out.push_back(v[i].get<double>());
  }
  return out;
}

Eigen::Vector3d JsonReader::vec3(const std::string& key) const {
  const auto a = fixed_numbers<3>(key);
  return {a[0], a[1], a[2]};
}

Eigen::Matrix3d JsonReader::mat3(const std::string& key) const {
  const Json& v = raw(key);
  if (!v.is_array() || v.size() != 3) fail(key, "expected a 3 x 3 matrix [[..],[..],[..]]");
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r) {
    if (!v[r].is_array() || v[r].size() != 3) fail(key, "expected a 3 x 3 matrix [[..],[..],[..]]");
    for (int c = 0; c < 3; ++c) {
      if (!v[r][c].is_number()) fail(key, "matrix entries must be numbers");
      m(r, c) = v[r][c].get<double>();
    }
  }
  return m;
}

JsonReader JsonReader::child(const std::string& key) const {
  const Json& v = raw(key);
  if (!v.is_object()) fail(key, "expected a JSON object");
  return JsonReader(v, file_, field(key));
}

double JsonReader::number_or(const std::string& key, double fallback) const {
  return has(key) ? number(key) : fallback;
}
int JsonReader::integer_or(const std::string& key, int fallback) const {
  return has(key) ? integer(key) : fallback;
}
std::string JsonReader::string_or(const std::string& key, const std::string& fallback) const {
  return has(key) ? string(key) : fallback;
}
bool JsonReader::boolean_or(const std::string& key, bool fallback) const {
  return has(key) ? boolean(key) : fallback;
}

double JsonReader::positive(const std::string& key) const {
  const double x = number(key);
  if (!(x > 0.0)) fail(key, "must be positive");
  return x;
}

double JsonReader::non_negative(const std::string& key) const {
  const double x = number(key);
  if (!(x >= 0.0)) fail(key, "must not be negative");
  return x;
}

void JsonReader::finish() const {
  for (auto it = object_.begin(); it != object_.end(); ++it) {
    if (!used_.count(it.key())) {
      std::ostringstream known;
      for (const auto& k : used_) known << (known.tellp() > 0 ? ", " : "") << k;
      std::string value = it.value().dump();
      if (value.size() > 80) value = value.substr(0, 77) + "...";
      throw ConfigError(file_ + ": field '" + field(it.key()) + "': unknown key (value " + value +
                        "; known keys here: " + known.str() + ")");
    }
  }
}

}  // namespace rover::io
