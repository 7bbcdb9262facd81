// See json_reader.hpp.
#include "io/json_reader.hpp"

#include <cerrno>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <system_error>
#include <utility>
#include <vector>

#include "io/json_syntax_message.hpp"
#include "io/nearest_name.hpp"
#include "io/text_encoding.hpp"

namespace rover::io {
namespace {

// The largest integer below which every integer is a double (2^53): an
// integral double beyond it need not be the integer that was written.
constexpr double kLargestExactInteger = 9007199254740992.0;

std::string shortened_dump(const Json& value) {
  std::string text = value.dump();
  if (text.size() > 80) text = text.substr(0, 77) + "...";
  return text;
}

// "line:column" (1-based) of byte `offset` of `text`.
std::string line_and_column(const std::string& text, std::size_t offset) {
  offset = std::min(offset, text.size());
  std::size_t line = 1, line_start = 0;
  for (std::size_t i = 0; i < offset; ++i)
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  return std::to_string(line) + ":" + std::to_string(offset - line_start + 1);
}

// Builds the DOM from nlohmann's SAX events, refusing a key repeated within
// one object (nlohmann's own parser keeps the last value silently). Each
// open object or array is kept with its dotted field path for the messages.
class StrictDomBuilder final : public nlohmann::json_sax<Json> {
 public:
  StrictDomBuilder(const std::string& text, const std::string& source)
      : text_(text), source_(source) {}

  Json& result() { return root_; }
  const std::string& error() const { return error_; }

  bool null() override { return add(Json(nullptr)); }
  bool boolean(bool value) override { return add(Json(value)); }
  bool number_integer(number_integer_t value) override { return add(Json(value)); }
  bool number_unsigned(number_unsigned_t value) override { return add(Json(value)); }
  bool number_float(number_float_t value, const string_t& text) override {
    // A number below the smallest double reads as 0: refused, as one above
    // the largest is (1e-400 is no zero that the user wrote).
    const std::string_view mantissa = std::string_view(text).substr(0, text.find_first_of("eE"));
    if (value == 0.0 && mantissa.find_first_of("123456789") != std::string_view::npos) {
      error_ = source_ + ": " + (open_.empty() ? std::string() : "field '" + next_path() + "': ") + "number " + text +
               " is below the smallest double (about 4.9e-324) and would read as 0; write 0, or the value in "
               "other units";
      return false;
    }
    return add(Json(value));
  }
  bool string(string_t& value) override { return add(Json(std::move(value))); }
  bool binary(binary_t& value) override { return add(Json::binary(std::move(value))); }

  bool start_object(std::size_t /*elements*/) override { return open(Json::object()); }
  bool start_array(std::size_t /*elements*/) override { return open(Json::array()); }
  bool end_object() override { return close(); }
  bool end_array() override { return close(); }

  bool key(string_t& name) override {
    Level& object = open_.back();
    if (object.value->contains(name)) {
      error_ = source_ + ": field '" + child_path(object.path, name) +
               "': key given twice in one object (first value " +
               shortened_dump(object.value->at(name)) + "); keep one";
      return false;
    }
    object.key = name;
    return true;
  }

  bool parse_error(std::size_t position, const std::string& last_token,
                   const Json::exception& problem) override {
    constexpr int kNumberOverflow = 406;  // nlohmann's out_of_range.406
    const bool overflow = problem.id == kNumberOverflow;
    // `position` is just past the offending character; an overflowing
    // number is reported at its first digit.
    const std::size_t offending = overflow ? position - std::min(position, last_token.size())
                                           : position - std::min<std::size_t>(position, 1);
    std::string where = source_ + ":" + line_and_column(text_, offending) + ": ";
    if (!open_.empty()) {
      const Level& level = open_.back();
      const std::string field =
          level.value->is_object() ? child_path(level.path, level.key) : level.path;
      if (!field.empty()) where += "field '" + field + "': ";
    }
    if (overflow) {
      error_ = where + "number " + last_token +
               " is beyond the range of a double (largest magnitude about 1.8e308)";
      return false;
    }
    // nlohmann's message after its "[json.exception...] ... column N: " prefix.
    std::string reason = problem.what();
    if (const std::size_t column = reason.find("column "); column != std::string::npos)
      if (const std::size_t colon = reason.find(": ", column); colon != std::string::npos)
        reason = reason.substr(colon + 2);
    error_ = where + "invalid JSON: " + json_syntax_problem(reason, text_, offending);
    return false;
  }

 private:
  struct Level {
    Json* value;       // the open object or array
    std::string path;  // its field path ("" for the top level)
    std::string key;   // objects: the key whose value comes next
  };

  // The field path of the value that comes next.
  std::string next_path() const {
    const Level& level = open_.back();
    if (level.value->is_object()) return child_path(level.path, level.key);
    return level.path + "[" + std::to_string(level.value->size()) + "]";
  }

  static std::string child_path(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }

  // Stores `value` where the next value goes; returns its slot and path.
  std::pair<Json*, std::string> place(Json value) {
    if (open_.empty()) {
      root_ = std::move(value);
      return {&root_, ""};
    }
    Level& parent = open_.back();
    if (parent.value->is_array()) {
      const std::string path = parent.path + "[" + std::to_string(parent.value->size()) + "]";
      parent.value->push_back(std::move(value));
      return {&parent.value->back(), path};
    }
    Json& slot = (*parent.value)[parent.key];
    slot = std::move(value);
    return {&slot, child_path(parent.path, parent.key)};
  }

  bool add(Json value) {
    place(std::move(value));
    return true;
  }
  bool open(Json container) {
    auto [slot, path] = place(std::move(container));
    open_.push_back({slot, std::move(path), ""});
    return true;
  }
  bool close() {
    open_.pop_back();
    return true;
  }

  const std::string& text_;
  const std::string& source_;
  Json root_;
  std::vector<Level> open_;  // pointers into root_: map nodes and the last array element stay put
  std::string error_;
};

// "a pipe", "a device", ... for a file that exists and is not a regular file.
std::string special_file_kind(const std::filesystem::file_status& status) {
  namespace fs = std::filesystem;
  if (fs::is_fifo(status)) return "a pipe";
  if (fs::is_character_file(status) || fs::is_block_file(status)) return "a device";
  if (fs::is_socket(status)) return "a socket";
  return "a special file";
}

}  // namespace

std::size_t json_nesting_excess(const std::string& text) {
  std::size_t depth = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"') {  // a string: up to its unescaped closing quote
      for (++i; i < text.size() && text[i] != '"'; ++i)
        if (text[i] == '\\') ++i;
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '/') {  // a comment to the end of the line
      i = std::min(text.find('\n', i), text.size());
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {  // a block comment
      i = std::min(text.find("*/", i + 2), text.size()) + 1;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonNesting) return i;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return std::string::npos;
}

Json parse_json_quietly(const std::string& text) {
  if (json_nesting_excess(text) != std::string::npos) return Json(Json::value_t::discarded);
  return Json::parse(text, nullptr, /*allow_exceptions=*/false, /*ignore_comments=*/true);
}


Json parse_json_text(const std::string& text, const std::string& source) {
  if (const std::string problem = text_encoding_problem(text); !problem.empty()) {
    const bool binary = problem.starts_with("holds a NUL byte");  // not UTF-16: where it is helps
    throw ConfigError(source + (binary ? ":" + line_and_column(text, text.find('\0')) : std::string()) + ": " +
                      problem + ": save a config as UTF-8 (plain JSON text)");
  }
  // RFC 8259, section 8.1: JSON text is UTF-8, in comments too.
  if (const std::size_t invalid = invalid_utf8_offset(text); invalid != std::string::npos)
    throw ConfigError(source + ":" + line_and_column(text, invalid) + ": is not UTF-8 text: " +
                      invalid_utf8_description(text, invalid) +
                      " (Latin-1 or Windows-1252 text?): save a config as UTF-8 (plain JSON text)");
  // Refused before any parsing: the builder's field paths grow with the depth.
  if (const std::size_t excess = json_nesting_excess(text); excess != std::string::npos)
    throw ConfigError(source + ":" + line_and_column(text, excess) + ": objects and arrays nested deeper than " +
                      std::to_string(kMaxJsonNesting) + " levels (a rover config nests a few): not a config file");
  StrictDomBuilder builder(text, source);
  const bool ok = Json::sax_parse(text, &builder, Json::input_format_t::json, /*strict=*/true,
                                  /*ignore_comments=*/true);
  if (!ok) {
    if (!builder.error().empty()) throw ConfigError(builder.error());
    throw ConfigError(source + ": invalid JSON");
  }
  return std::move(builder.result());
}

std::string input_path_problem(const std::string& path, const std::string& kind) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (fs::is_directory(status)) return "is a directory, not " + kind;
  if (error && error != std::errc::no_such_file_or_directory && error != std::errc::not_a_directory)
    return "cannot be reached (" + error.message() +
           (error == std::errc::too_many_symbolic_link_levels ? ": a symbolic link that leads back to itself?)" : ")");
  if (!fs::exists(status)) {
    if (fs::is_symlink(fs::symlink_status(path, error)))
      return "is a symbolic link to '" + fs::read_symlink(path, error).string() + "', which does not exist";
    return "no such file";
  }
  if (!fs::is_regular_file(status))
    return "is " + special_file_kind(status) + ", not " + kind +
           ": rover reads an input more than once (on every MPI rank, and again for the fingerprint --resume "
           "checks), which only a file can give; save it to a file";
  return "";
}

std::string read_json_text(const std::string& path) {
  if (const std::string problem = input_path_problem(path, "a JSON file"); !problem.empty())
    throw ConfigError(path + ": " + problem);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path + ": cannot open file");
  std::string text;
  try {  // the stream buffer throws on a failed read(2) (EIO: /proc/self/mem)
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  } catch (const std::exception&) {
    throw ConfigError(path + ": read error (" + std::generic_category().message(errno) + ")");
  }
  if (in.bad()) throw ConfigError(path + ": read error");
  return text;
}

Json read_json_file(const std::string& path) { return parse_json_text(read_json_text(path), path); }

std::optional<std::uint64_t> exact_unsigned_integer(const Json& value) {
  if (value.is_number_unsigned()) return value.get<std::uint64_t>();
  if (value.is_number_integer()) {
    const std::int64_t signed_value = value.get<std::int64_t>();
    if (signed_value < 0) return std::nullopt;
    return static_cast<std::uint64_t>(signed_value);
  }
  if (value.is_number_float()) {
    const double x = value.get<double>();
    if (std::isfinite(x) && x >= 0.0 && x <= kLargestExactInteger && std::floor(x) == x)
      return static_cast<std::uint64_t>(x);
  }
  return std::nullopt;
}

std::string whole_number_rule(const IntegerRange& range) {
  return "must be a whole number " +
         (range.accepted.empty() ? "from " + std::to_string(range.min) + " to " + std::to_string(range.max)
                                 : range.accepted);
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
  if (object_.contains(key)) value = " (value " + shortened_dump(object_.at(key)) + ")";
  throw ConfigError(file_ + ": field '" + field(key) + "'" + value + ": " + problem +
                    (object_.contains(key) ? "" : misspelling_note(key)));
}

std::string JsonReader::misspelling_note(const std::string& key) const {
  // Short keys ("min", "max", "f") are near each other: only one edit, and
  // none for a key of one or two characters.
  constexpr std::size_t kShortKey = 4, kMinKey = 3;
  if (key.size() < kMinKey) return "";
  const std::size_t max_edits = key.size() <= kShortKey ? 1 : 2;
  std::string nearest;
  std::size_t best = max_edits + 1;
  for (auto it = object_.begin(); it != object_.end(); ++it) {
    if (used_.count(it.key())) continue;  // a key read as itself
    if (const std::size_t distance = edit_distance(it.key(), key); distance < best) {
      best = distance;
      nearest = it.key();
    }
  }
  if (nearest.empty()) return "";
  return " (the object has '" + nearest + "', not a field name: a misspelling of '" + key + "'?)";
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

int JsonReader::integer(const std::string& key, const IntegerRange& range) const {
  const Json& v = raw(key);
  std::optional<long long> whole;
  if (v.is_number_unsigned()) {
    const std::uint64_t u = v.get<std::uint64_t>();
    if (u <= static_cast<std::uint64_t>(INT_MAX)) whole = static_cast<long long>(u);
  } else if (v.is_number_integer()) {
    whole = v.get<std::int64_t>();
  } else if (v.is_number_float()) {
    const double x = v.get<double>();
    if (std::isfinite(x) && std::floor(x) == x && std::fabs(x) <= kLargestExactInteger) whole = static_cast<long long>(x);
  }
  if (!whole || *whole < range.min || *whole > range.max) fail(key, whole_number_rule(range));
  return static_cast<int>(*whole);
}

std::uint64_t JsonReader::count(const std::string& key) const {
  const std::optional<std::uint64_t> n = exact_unsigned_integer(raw(key));
  if (!n) fail(key, std::string("expected a count, an integer from 0 to 18446744073709551615") + kExponentFormLimit);
  return *n;
}

std::uint64_t JsonReader::seed(const std::string& key) const {
  const std::optional<std::uint64_t> n = exact_unsigned_integer(raw(key));
  if (!n) fail(key, std::string("expected a seed, an integer from 0 to 18446744073709551615") + kExponentFormLimit);
  return *n;
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
int JsonReader::integer_or(const std::string& key, int fallback, const IntegerRange& range) const {
  return has(key) ? integer(key, range) : fallback;
}
std::uint64_t JsonReader::count_or(const std::string& key, std::uint64_t fallback) const {
  return has(key) ? count(key) : fallback;
}
std::uint64_t JsonReader::seed_or(const std::string& key, std::uint64_t fallback) const {
  return has(key) ? seed(key) : fallback;
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
      throw ConfigError(file_ + ": field '" + field(it.key()) + "': unknown key (value " +
                        shortened_dump(it.value()) +
                        "; known keys here: " + known.str() + ")");
    }
  }
}

}  // namespace rover::io
