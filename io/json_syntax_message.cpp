// See json_syntax_message.hpp.
#include "io/json_syntax_message.hpp"

#include <algorithm>
#include <cctype>
#include <string_view>

namespace rover::io {
namespace {

constexpr std::size_t kLongestQuotedWord = 24;  // characters of an offending word shown

bool contains(std::string_view text, std::string_view part) { return text.find(part) != std::string_view::npos; }

// The word that starts at `offset`: "NaN", "True", "'x'", ".5".
std::string word_at(const std::string& text, std::size_t offset) {
  std::size_t end = offset;
  while (end < text.size() && end - offset < kLongestQuotedWord &&
         (std::isalnum(static_cast<unsigned char>(text[end])) || std::string_view("'._+-").find(text[end]) != std::string_view::npos))
    ++end;
  return text.substr(offset, std::max<std::size_t>(end - offset, offset < text.size() ? 1 : 0));
}

// What the parser found instead: "a string", "a number", "'}'", "the end of the file".
std::string found(std::string_view reason) {
  const std::size_t at = reason.find("unexpected ");
  if (at == std::string_view::npos) return "something else";
  std::string_view token = reason.substr(at + 11);
  token = token.substr(0, token.find(';'));
  if (token == "string literal") return "a string";
  if (token == "number literal") return "a number";
  if (token == "end of input") return "the end of the file";
  if (token.starts_with("'")) return std::string(token);
  return "something else";
}

// The character before `offset`, skipping white space: ',' for "[1, ]".
char previous_character(const std::string& text, std::size_t offset) {
  while (offset > 0) {
    const char c = text[--offset];
    if (!std::isspace(static_cast<unsigned char>(c))) return c;
  }
  return '\0';
}

// The first character of the number that ends at or before `offset`.
std::size_t number_start(const std::string& text, std::size_t offset) {
  std::size_t start = std::min(offset, text.size());
  while (start > 0 && std::string_view("0123456789.eE+-").find(text[start - 1]) != std::string_view::npos) --start;
  return start;
}

std::string lower(std::string word) {
  std::transform(word.begin(), word.end(), word.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return word;
}

std::string invalid_literal(const std::string& word) {
  const std::string w = lower(word);
  if (word.starts_with("'")) return "single quotes: JSON strings and keys take double quotes (\"...\")";
  if (w == "nan" || w == "inf" || w == "infinity" || w == "-inf" || w == "-infinity")
    return "'" + word + "' is not a JSON number: give a finite number";
  if (word.starts_with(".")) return "'" + word + "' is not a JSON number: write a digit before the point (0.5)";
  if (w == "true" || w == "false" || w == "null")
    return "'" + word + "': JSON writes true, false and null in lower case";
  return "'" + word + "' is not a JSON value: a string takes double quotes (\"" + word + "\")";
}

std::string invalid_string(std::string_view reason) {
  if (contains(reason, "control character"))
    return "a control character (a tab or a line break) inside a string: write a tab as \\t, or close the string "
           "with '\"'";
  if (contains(reason, "missing closing quote")) return "a string without its closing '\"'";
  if (contains(reason, "surrogate U+"))
    return "a lone UTF-16 surrogate escape: \\uD800 to \\uDBFF must be followed by \\uDC00 to \\uDFFF, which "
           "must follow one (a pair escapes one character beyond U+FFFF); write the character itself, or its "
           "whole pair";
  if (contains(reason, "'\\u' must be followed by 4 hex digits"))
    return "\\u must be followed by 4 hex digits (\\u00e9)";
  return "a backslash in a string starts an escape (\\n, \\t, \\\", \\\\): write a backslash itself as \\\\ "
         "(a Windows path?)";
}

}  // namespace

std::string json_syntax_problem(const std::string& library_reason, const std::string& text, std::size_t offending) {
  const std::string_view reason = library_reason;
  if (contains(reason, "unexpected end of input")) {
    const bool blank = std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isspace(c); });
    return blank ? "the file holds no JSON (it is empty)"
                 : "the text ends before the JSON does: close every '{' with '}' and every '[' with ']'";
  }
  if (contains(reason, "invalid string")) return invalid_string(reason);
  if (contains(reason, "invalid number"))
    return "'" + word_at(text, number_start(text, offending)) +
           "' is not a JSON number: write digits after a sign, a point and an exponent (-1, 5.0, 1e-3)";
  if (contains(reason, "invalid literal")) return invalid_literal(word_at(text, offending));
  if (contains(reason, "expected end of input"))
    return "text after the end of the JSON: an extra '}' or ']', or a second object";
  if (contains(reason, "parsing object key"))
    return found(reason) == "'}'" ? "a comma before '}': JSON allows no comma after an object's last entry"
                                  : "expected a key in double quotes, found " + found(reason);
  if (contains(reason, "parsing object separator")) return "expected ':' after the key, found " + found(reason);
  // "09.81": nlohmann reads the 0 as a number and the 9.81 as the next value.
  if (contains(reason, "parsing object -") || contains(reason, "parsing array -")) {
    std::size_t start = number_start(text, offending);
    const std::size_t word = start;
    if (start < text.size() && text[start] == '-') ++start;
    std::size_t digits = start;
    while (digits + 1 < text.size() && text[digits] == '0' && std::isdigit(static_cast<unsigned char>(text[digits + 1])))
      ++digits;
    if (digits > start)
      return "'" + word_at(text, word) + "' is not a JSON number: a number starts with no 0 before other digits (" +
             "write " + text.substr(word, start - word) + word_at(text, digits) + ")";
  }
  if (contains(reason, "parsing object -"))
    return "expected ',' or '}' after a value, found " + found(reason) + " (a missing comma?)";
  if (contains(reason, "parsing array -"))
    return "expected ',' or ']' after a value, found " + found(reason) + " (a missing comma?)";
  if (found(reason) == "']'" && previous_character(text, offending) == ',')
    return "a comma before ']': JSON allows no comma after an array's last element";
  return "expected a value (a number, a string in double quotes, true, false, null, an object or an array), found " +
         found(reason);
}

}  // namespace rover::io
