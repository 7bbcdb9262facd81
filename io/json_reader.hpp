// Reading JSON configs with errors that name the file, the field and the value.
//
// JsonReader wraps one JSON object together with the file it came from and
// its dotted path ("bodies.wheel"). Every accessor records the keys it read,
// so finish() can reject unknown (typically misspelt) keys.
//
// Parsing is stricter than RFC 8259 requires, where the RFC leaves the
// choice to the reader: a key repeated in one object is an error (RFC 8259
// section 4 only says such names "SHOULD be unique"), and so is a number
// beyond the range of a double (section 6). Integers never wrap: integer(),
// count() and seed() accept exactly the values of their type.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
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

// Parses a JSON file (comments allowed); a missing file, a directory, a syntax
// error, a number out of the range of a double or a key repeated within one
// object becomes a ConfigError naming the file and the line and column, or
// the field ("path: field 'bodies.wheel.mass': key given twice ...").
Json read_json_file(const std::string& path);

// The text of the JSON file `path`, unparsed, with read_json_file()'s errors
// for a path that names no readable file.
std::string read_json_text(const std::string& path);

// Why `path` names no file to read, or empty: "no such file", "is a
// directory, not <kind>" ("a JSON file"), "cannot be reached (Too many levels
// of symbolic links: a link that leads back to itself?)", "is a pipe, not
// <kind>: ..." (an input is read more than once: only a regular file will do).
std::string input_path_problem(const std::string& path, const std::string& kind);

// The same for JSON text; `source` names it in messages (a file name).
Json parse_json_text(const std::string& text, const std::string& source);

// Objects and arrays nested deeper than this are refused before parsing (a
// rover config nests a few levels; a file of thousands would cost memory
// growing with the square of its depth): "path:line:column: ... nested
// deeper than 100 levels".
inline constexpr std::size_t kMaxJsonNesting = 100;

// The byte offset in `text` of the bracket that opens a level beyond
// kMaxJsonNesting, or std::string::npos; brackets inside strings and
// comments do not count.
std::size_t json_nesting_excess(const std::string& text);

// `text` parsed (comments allowed) for a reader that only looks into a file
// its loader reads later and reports on: a discarded value for text that is
// no JSON or nests deeper than kMaxJsonNesting.
Json parse_json_quietly(const std::string& text);

// The value of a JSON number as an unsigned 64-bit integer, if it is one
// exactly: a JSON integer in [0, 2^64 - 1], or an integral floating-point
// number (1e3) up to 2^53, beyond which a double need not hold the integer
// that was written. Empty for anything else (negative, fractional, 2^64 + 5,
// not a number).
std::optional<std::uint64_t> exact_unsigned_integer(const Json& value);
// Appended to the range of such an integer: a number in exponent or decimal
// form is a double, exact as an integer only up to 2^53.
inline constexpr const char* kExponentFormLimit =
    " (in exponent form, as 1e3, at most 2^53 = 9007199254740992: write larger ones in digits)";

// The whole numbers an integer field accepts: those from `min` to `max`;
// `accepted`, when given, states them in place of "from <min> to <max>"
// where the caller refuses more than the two bounds do ("0 (no intervals), or
// from 100 to 100000"; "even, from 2 to 100000").
struct IntegerRange {
  int min = 0;
  int max = 0;
  std::string accepted{};
};

// "must be a whole number from 1 to 1000000", or with range.accepted.
std::string whole_number_rule(const IntegerRange& range);

class JsonReader {
 public:
  JsonReader(const Json& object, std::string file, std::string path = "");

  bool has(const std::string& key) const;
  // Required values.
  double number(const std::string& key) const;
  // An int from range.min to range.max: a JSON integer, or an integral
  // number written with a point or an exponent (10.0, 1e1); 2.5, -5 below a
  // minimum of 1 and 4294967298 are refused, never rounded or wrapped, with
  // whole_number_rule(range).
  int integer(const std::string& key, const IntegerRange& range) const;
  // A non-negative 64-bit count (samples, evaluations) and a 64-bit seed:
  // exact_unsigned_integer() of the value, refused otherwise ("samples":
  // 4294967298 stays 4294967298; -1 and 2^64 + 5 are errors).
  std::uint64_t count(const std::string& key) const;
  std::uint64_t seed(const std::string& key) const;
  std::string string(const std::string& key) const;
  bool boolean(const std::string& key) const;
  std::vector<double> numbers(const std::string& key) const;
  Eigen::Vector3d vec3(const std::string& key) const;
  Eigen::Matrix3d mat3(const std::string& key) const;
  JsonReader child(const std::string& key) const;
  // Optional values: the fallback when the key is absent.
  double number_or(const std::string& key, double fallback) const;
  int integer_or(const std::string& key, int fallback, const IntegerRange& range) const;
  std::uint64_t count_or(const std::string& key, std::uint64_t fallback) const;
  std::uint64_t seed_or(const std::string& key, std::uint64_t fallback) const;
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

  // Throws ConfigError "<file>: field '<path.key>' (value ...): <problem>";
  // for a key the object lacks, naming a key of the object that is one or
  // two edits from it ("distribuion" for "distribution"), if any.
  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;
  std::string field(const std::string& key) const;  // "path.key"
  const Json& raw(const std::string& key) const;
  const std::string& file() const { return file_; }
  const Json& raw_object() const { return object_; }

 private:
  // " (the object has 'distribuion', ...: a misspelling of 'distribution'?)", or empty.
  std::string misspelling_note(const std::string& key) const;

  const Json& object_;
  std::string file_, path_;
  mutable std::set<std::string> used_;
};

}  // namespace rover::io
