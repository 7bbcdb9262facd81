// Reading JSON configs with errors that name the file, the field and the value.
//
// JsonReader wraps one JSON object together with the file it came from and
// its dotted path ("bodies.wheel"). Every accessor records the keys it read,
// so finish() can reject unknown (typically misspelt) keys.
#pragma once

#include <array>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace rover::io {

// ordered_json keeps a file's key order: studies list their inputs in the order written.
using Json = nlohmann::ordered_json;

// A bad input file: the message names the file, the field and the value.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Parses a JSON file; a missing file or a syntax error becomes a ConfigError.
Json read_json_file(const std::string& path);

class JsonReader {
 public:
  JsonReader(const Json& object, std::string file, std::string path = "");

  bool has(const std::string& key) const;
  // Required values.
  double number(const std::string& key) const;
  int integer(const std::string& key) const;
  std::string string(const std::string& key) const;
  bool boolean(const std::string& key) const;
  std::vector<double> numbers(const std::string& key) const;
  Eigen::Vector3d vec3(const std::string& key) const;
  Eigen::Matrix3d mat3(const std::string& key) const;
  JsonReader child(const std::string& key) const;
  // Optional values: the fallback when the key is absent.
  double number_or(const std::string& key, double fallback) const;
  int integer_or(const std::string& key, int fallback) const;
  std::string string_or(const std::string& key, const std::string& fallback) const;
  bool boolean_or(const std::string& key, bool fallback) const;
  template <std::size_t N>
  std::array<double, N> fixed_numbers(const std::string& key) const {
    const std::vector<double> v = numbers(key);
    if (v.size() != N)
      fail(key, "expected " + std::to_string(N) + " numbers, got " + std::to_string(v.size()));
    std::array<double, N> out{};
    for (std::size_t i = 0; i < N; ++i) out[i] = v[i];
    return out;
  }

  // Range checks: throw naming the field and the value.
  double positive(const std::string& key) const;      // > 0
  double non_negative(const std::string& key) const;  // >= 0

  // Throws if the object holds a key that no accessor asked for.
  void finish() const;

  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;
  std::string field(const std::string& key) const;  // "path.key"
  const Json& raw(const std::string& key) const;
  const std::string& file() const { return file_; }
  const Json& raw_object() const { return object_; }

 private:
  const Json& object_;
  std::string file_, path_;
  mutable std::set<std::string> used_;
};

}  // namespace rover::io
