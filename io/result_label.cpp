// See result_label.hpp.
#include "io/result_label.hpp"

#include <algorithm>
#include <cstdio>

namespace rover::io {
namespace {

constexpr unsigned char kFirstPrintable = 0x20;
constexpr unsigned char kDelete = 0x7f;

bool is_control(char c) {
  const auto byte = static_cast<unsigned char>(c);
  return byte < kFirstPrintable || byte == kDelete;
}

// The name as it can be shown: control characters as \xNN, at most 80 bytes.
std::string shown(const std::string& name) {
  constexpr std::size_t kShownBytes = 80;
  std::string text;
  for (std::size_t i = 0; i < name.size() && i < kShownBytes; ++i) {
    if (!is_control(name[i])) {
      text += name[i];
      continue;
    }
    char escaped[8];
    std::snprintf(escaped, sizeof escaped, "\\x%02x", static_cast<unsigned char>(name[i]));
    text += escaped;
  }
  if (name.size() > kShownBytes) text += "...";
  return "'" + text + "'";
}

// The checks both kinds of name share: not empty, not too long, no control characters.
std::string length_or_control_problem(const std::string& name, std::size_t max_length, const std::string& rule) {
  if (name.empty()) return "is empty" + rule;
  if (name.size() > max_length) return shown(name) + " has " + std::to_string(name.size()) + " characters" + rule;
  if (std::any_of(name.begin(), name.end(), is_control)) return shown(name) + " holds a control character" + rule;
  return "";
}

}  // namespace

std::string result_label_problem(const std::string& label) {
  const std::string rule = " (it names HDF5 datasets, figure files and CSV columns: give 1 to " +
                           std::to_string(kMaxResultLabelLength) +
                           " characters without '/', '\\', ',', '\"', \"..\" or control characters, and not \".\")";
  if (std::string problem = length_or_control_problem(label, kMaxResultLabelLength, rule); !problem.empty())
    return problem;
  if (const std::size_t at = label.find_first_of("/\\,\""); at != std::string::npos)
    return shown(label) + " holds '" + label.substr(at, 1) + "'" + rule;
  if (label.find("..") != std::string::npos) return shown(label) + " holds \"..\"" + rule;
  if (label == ".") return shown(label) + " names no dataset (the group itself)" + rule;
  return "";
}

std::string display_name_problem(const std::string& name) {
  return length_or_control_problem(
      name, kMaxDisplayNameLength,
      " (give 1 to " + std::to_string(kMaxDisplayNameLength) + " characters without control characters)");
}

}  // namespace rover::io
