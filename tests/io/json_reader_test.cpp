// Tests of io/json_reader: what the strict parser refuses (a key repeated in
// one object, numbers beyond a double, directories, syntax errors) with the
// file and the line and column or the field in the message, and integer
// accessors that never round or wrap (int, 64-bit counts and seeds).
#include "io/json_reader.hpp"

#include <gtest/gtest.h>

#include <climits>
#include <cstdint>
#include <functional>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace rover::io {
namespace {

std::string write_text(const std::string& text) {
  const std::string path = testing::temp_dir() + "/config.json";
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// The message of the ConfigError that read_json_file throws (fails the test if none).
std::string read_error(const std::string& path) {
  try {
    read_json_file(path);
  } catch (const ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << path << " was read without error";
  return "";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(JsonReader, KeyRepeatedInOneObjectIsAnErrorNamingTheField) {
  struct Case {
    std::string text, field, first_value;
  };
  const std::vector<Case> cases = {
      {R"({"samples": 10, "samples": 20})", "samples", "10"},
      {R"({"bodies": {"wheel": {"mass": 1.5, "com": [0, 0, 0], "mass": 2.5}}})",
       "bodies.wheel.mass", "1.5"},
      {R"({"drive": {"segments": [{"mode": "car"}, {"mode": "car", "mode": "lateral"}]}})",
       "drive.segments[1].mode", "\"car\""},
      {"{\n  \"a\": {\"x\": 1},\n  // a comment\n  \"a\": [1, 2]\n}", "a", "{\"x\":1}"},
      {R"([{"k": null}, {"k": true, "k": false}])", "[1].k", "true"},
  };
  for (const Case& c : cases) {
    const std::string path = write_text(c.text);
    const std::string message = read_error(path);
    EXPECT_TRUE(contains(message, path + ": field '" + c.field + "'")) << message;
    EXPECT_TRUE(contains(message, "given twice")) << message;
    EXPECT_TRUE(contains(message, "first value " + c.first_value)) << message;
  }
  // The same key in different objects, and keys differing in case, are fine.
  const Json ok = parse_json_text(R"({"a": {"k": 1}, "b": {"k": 2}, "K": 3, "k": [{"k": 4}, {"k": 5}]})",
                                  "ok.json");
  EXPECT_EQ(ok.at("b").at("k"), 2);
  EXPECT_EQ(ok.at("k").at(1).at("k"), 5);
  EXPECT_EQ(ok.at("K"), 3);
}

TEST(JsonReader, ParsedValuesEqualNlohmannsOwnParse) {
  const std::string text = R"({"a": [1, -2, 3.5, 1e-300, "s", null, true, {"b": []}], "c": {}, "u": 18446744073709551615})";
  EXPECT_EQ(parse_json_text(text, "t.json"), Json::parse(text));
  EXPECT_TRUE(parse_json_text(text, "t.json").at("u").is_number_unsigned());
}

TEST(JsonReader, NumberBeyondADoubleNamesFileLineColumnAndField) {
  struct Case {
    std::string text, where, field;
  };
  const std::vector<Case> cases = {
      {R"({"duration": 1e999})", ":1:14: field 'duration'", "1e999"},
      {"{\n  \"inputs\": {\n    \"f\": -1E400}}", ":3:10: field 'inputs.f'", "-1E400"},
      {"{\"M0\": [1, 2,\n 1e308, 2e308]}", ":2:9: field 'M0'", "2e308"},
  };
  for (const Case& c : cases) {
    const std::string path = write_text(c.text);
    const std::string message = read_error(path);
    EXPECT_TRUE(contains(message, path + c.where)) << message;
    EXPECT_TRUE(contains(message, "number " + c.field + " is beyond the range of a double")) << message;
  }
}

TEST(JsonReader, SyntaxErrorsNameLineAndColumn) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{\n  \"a\": 1,\n  \"b\": x\n}", ":3:8: field 'b': "},
      {"{\"a\": 1,}", ":1:9: "},
      {"{\"a\": [1, 2}", ":1:12: field 'a': "},
      {"", ":1:1: "},
  };
  for (const auto& [text, where] : cases) {
    const std::string path = write_text(text);
    const std::string message = read_error(path);
    EXPECT_TRUE(contains(message, path + where)) << text << " -> " << message;
    EXPECT_TRUE(contains(message, "invalid JSON")) << message;
  }
}

// Each kind of typo gets plain words saying what to change, and none of the
// JSON library's own ("syntax error while parsing", "literal", "last read").
TEST(JsonReader, SyntaxErrorsSayWhatToChange) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{\"type\": \"montecarlo\", \"name\": \"x\",}", "a comma before '}'"},
      {"{\"a\": [1, 2,]}", "a comma before ']'"},
      {"{'a': 1}", "single quotes"},
      {"{\"a\": 'x'}", "single quotes"},
      {"{\"a\" 1}", "expected ':' after the key, found a number"},
      {"{\"a\": 1 \"b\": 2}", "expected ',' or '}' after a value, found a string (a missing comma?)"},
      {"[1 2]", "expected ',' or ']' after a value, found a number (a missing comma?)"},
      {"{\"a\": NaN}", "'NaN' is not a JSON number"},
      {"{\"a\": Infinity}", "'Infinity' is not a JSON number"},
      {"{\"a\": True}", "'True': JSON writes true, false and null in lower case"},
      {"{\"a\": yes}", "'yes' is not a JSON value: a string takes double quotes (\"yes\")"},
      {"{\"a\": .5}", "'.5' is not a JSON number: write a digit before the point"},
      {"{\"a\": 5.}", "'5.' is not a JSON number"},
      {"{\"a\": 1e}", "'1e' is not a JSON number"},
      {"{\"a\": \"x\ty\"}", "a control character (a tab or a line break) inside a string"},
      {"{\"a\": \"x", "a string without its closing '\"'"},
      {"{\"a\": \"C:\\new\\q\"}", "a backslash in a string starts an escape"},
      {"{\"a\": 1", "the text ends before the JSON does"},
      {"  \n", "the file holds no JSON (it is empty)"},
      {"{\"a\": 1}}", "text after the end of the JSON"},
      {"{\"a\": }", "expected a value"},
  };
  for (const auto& [text, words] : cases) {
    const std::string message = read_error(write_text(text));
    EXPECT_TRUE(contains(message, "invalid JSON: " + words)) << text << " -> " << message;
    for (const std::string library : {"syntax error while", "literal", "last read", "parse error"})
      EXPECT_FALSE(contains(message, library)) << text << " -> " << message;
  }
}

// Nesting: kMaxJsonNesting levels are read; one more is refused at the
// bracket that opens it, before any parsing; brackets in strings (also after
// an escaped quote) and in comments do not count.
TEST(JsonReader, NestingBeyondTheLimitIsRefusedWhereItBegins) {
  const std::size_t limit = kMaxJsonNesting;
  const std::string deepest = std::string(limit, '[') + std::string(limit, ']');
  EXPECT_EQ(json_nesting_excess(deepest), std::string::npos);
  EXPECT_NO_THROW(parse_json_text(deepest, "deep.json"));
  const std::string beyond = "{\n \"a\": " + std::string(limit, '[') + std::string(limit, ']') + "}";
  EXPECT_EQ(json_nesting_excess(beyond), 7 + limit);
  const std::string message = read_error(write_text(beyond));
  EXPECT_TRUE(contains(message, "config.json:2:" + std::to_string(6 + limit) + ": ")) << message;
  EXPECT_TRUE(contains(message, "nested deeper than " + std::to_string(limit) + " levels")) << message;
  const std::string quoted = std::string(limit, '[') + "\"[{\\\"[{\" // [[[ \n /* [[[ */" + std::string(limit, ']');
  EXPECT_EQ(json_nesting_excess(quoted), std::string::npos) << quoted;
  EXPECT_NO_THROW(parse_json_text(quoted, "quoted.json"));
  // A file of millions of levels is refused at once, never parsed.
  const std::string huge(3'000'000, '[');
  EXPECT_EQ(json_nesting_excess(huge), limit);
  EXPECT_TRUE(parse_json_quietly(huge).is_discarded());
  EXPECT_TRUE(parse_json_quietly("{\"a\": [1, 2]} // fine").is_object());
}

TEST(JsonReader, DirectoriesAndMissingFilesAreNamed) {
  const std::string dir = testing::temp_dir();
  EXPECT_EQ(read_error(dir), dir + ": is a directory, not a JSON file");
  EXPECT_EQ(read_error(dir + "/absent.json"), dir + "/absent.json: no such file");
}

// The value of `key` in {"n": text} read by `accessor`, or the error message.
template <class Accessor>
std::string read_value(const std::string& text, Accessor accessor) {
  const Json json = parse_json_text("{\"n\": " + text + "}", "counts.json");
  const JsonReader reader(json, "counts.json");
  try {
    return std::to_string(accessor(reader));
  } catch (const ConfigError& e) {
    return std::string("error: ") + e.what();
  }
}

TEST(JsonReader, IntegerAcceptsExactlyTheWholeNumbersOfItsRange) {
  const auto integer = [](const JsonReader& r) { return r.integer("n", {INT_MIN, INT_MAX}); };
  EXPECT_EQ(read_value("7", integer), "7");
  EXPECT_EQ(read_value("-3", integer), "-3");
  EXPECT_EQ(read_value("1e3", integer), "1000");
  EXPECT_EQ(read_value("10.0", integer), "10");
  EXPECT_EQ(read_value("2147483647", integer), "2147483647");
  EXPECT_EQ(read_value("-2147483648", integer), "-2147483648");
  for (const std::string bad : {"2.5", "4294967298", "2147483648", "-2147483649", "1e300",
                                "18446744073709551621", "\"7\"", "true", "null", "[1]"}) {
    const std::string result = read_value(bad, integer);
    EXPECT_TRUE(contains(result, "error: counts.json: field 'n'")) << bad << " -> " << result;
    EXPECT_TRUE(contains(result, "must be a whole number from -2147483648 to 2147483647")) << result;
  }
}

TEST(JsonReader, IntegerStatesTheRangeItEnforces) {
  const auto count = [](const JsonReader& r) { return r.integer("n", {1, 1000000}); };
  EXPECT_EQ(read_value("1e1", count), "10");
  for (const std::string bad : {"2.5", "0", "-5", "3e9", "1000001"}) {
    const std::string result = read_value(bad, count);
    EXPECT_TRUE(contains(result, "field 'n' (value ")) << bad << " -> " << result;
    EXPECT_TRUE(contains(result, "must be a whole number from 1 to 1000000")) << bad << " -> " << result;
  }
  const auto even = [](const JsonReader& r) { return r.integer("n", {2, 100, "that is even, from 2 to 100"}); };
  EXPECT_TRUE(contains(read_value("1.5", even), "must be a whole number that is even, from 2 to 100"));
}

TEST(JsonReader, TextThatIsNotUtf8IsNamedByLineColumnAndByte) {
  const auto message = [](const std::string& text) {
    try {
      parse_json_text(text, "c.json");
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string latin1 = message("{\n  \"name\": \"Caf\xe9 x\"\n}");
  EXPECT_TRUE(contains(latin1, "c.json:2:15: is not UTF-8 text: byte 0xE9")) << latin1;
  EXPECT_TRUE(contains(latin1, "save a config as UTF-8")) << latin1;
  EXPECT_FALSE(contains(latin1, "backslash")) << latin1;
  EXPECT_TRUE(contains(message("{\"a\": \"\xff\xfe x\"}"), "c.json:1:8: is not UTF-8 text: byte 0xFF"));
  const std::string truncated = message("{\"a\": \"x\xc3\"}");
  EXPECT_TRUE(contains(truncated, "1:9: is not UTF-8 text: byte 0xC3 begins a 2-byte UTF-8 character, but byte 0x22"))
      << truncated;
  EXPECT_EQ(message("{\"a\": \"Caf\xc3\xa9\"}"), "no error");
  const std::string surrogate = message("{\"a\": \"\\ud800\"}");
  EXPECT_TRUE(contains(surrogate, "a lone UTF-16 surrogate escape")) << surrogate;
  EXPECT_FALSE(contains(surrogate, "Windows path")) << surrogate;
}

TEST(JsonReader, CountsAndSeedsAreExact64BitIntegers) {
  const auto count = [](const JsonReader& r) { return r.count("n"); };
  const auto seed = [](const JsonReader& r) { return r.seed("n"); };
  for (const auto& accessor : {std::function<std::uint64_t(const JsonReader&)>(count),
                               std::function<std::uint64_t(const JsonReader&)>(seed)}) {
    EXPECT_EQ(read_value("4294967298", accessor), "4294967298");
    EXPECT_EQ(read_value("18446744073709551615", accessor), "18446744073709551615");
    EXPECT_EQ(read_value("0", accessor), "0");
    EXPECT_EQ(read_value("2e4", accessor), "20000");
    EXPECT_EQ(read_value("9007199254740992.0", accessor), "9007199254740992");
    // 2^64 and 2^64 + 5 arrive as doubles; 1e17 is a double beyond 2^53.
    for (const std::string bad : {"-1", "18446744073709551616", "18446744073709551621", "1.5",
                                  "1e17", "-0.5", "\"12\"", "false"}) {
      const std::string result = read_value(bad, accessor);
      EXPECT_TRUE(contains(result, "error: counts.json: field 'n' (value")) << bad << " -> " << result;
      EXPECT_TRUE(contains(result, "18446744073709551615")) << result;
    }
  }
  const Json json = parse_json_text(R"({"samples": 4294967298})", "c.json");
  const JsonReader r(json, "c.json");
  EXPECT_EQ(r.count_or("samples", 5), 4294967298u);
  EXPECT_EQ(r.seed_or("seed", 42), 42u);
  r.finish();
}

TEST(JsonReader, EveryUnsignedIntegerRoundTripsExactly) {
  std::mt19937_64 rng(20260101);
  for (int i = 0; i < 200; ++i) {
    const std::uint64_t value = rng() >> (i % 64);
    const Json json = parse_json_text("{\"seed\": " + std::to_string(value) + "}", "s.json");
    EXPECT_EQ(exact_unsigned_integer(json.at("seed")), value);
  }
  EXPECT_EQ(exact_unsigned_integer(Json(-1)), std::nullopt);
  EXPECT_EQ(exact_unsigned_integer(Json(std::numeric_limits<double>::infinity())), std::nullopt);
  EXPECT_EQ(exact_unsigned_integer(Json("1")), std::nullopt);
}

}  // namespace
}  // namespace rover::io
