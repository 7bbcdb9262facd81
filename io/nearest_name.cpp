// See nearest_name.hpp.
#include "io/nearest_name.hpp"

#include <algorithm>

namespace rover::io {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitution = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + substitution});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

namespace {

// A name's first word, without leading dashes: "crab" for "--crab-deg" and
// "--crab-angle", "noise" for "noise_sd"; `whole` is false for a one-word name.
struct LeadingWord {
  std::string_view word;
  bool whole = true;
};

LeadingWord leading_word(std::string_view name) {
  name.remove_prefix(std::min(name.find_first_not_of('-'), name.size()));
  const std::size_t end = name.find_first_of("-_");
  if (end == std::string_view::npos) return {name, true};
  return {name.substr(0, end), false};
}

// A word short enough to be shared by chance ("a", "no") names nothing.
constexpr std::size_t kMinSharedWordLength = 3;

// The one known name whose first word is that of a multi-word `typed`
// ("--crab-angle" -> "--crab-deg"); empty when none or several share it.
std::string only_name_sharing_first_word(std::string_view typed, const std::vector<std::string>& known) {
  const LeadingWord first = leading_word(typed);
  if (first.whole || first.word.size() < kMinSharedWordLength) return "";
  std::string found;
  for (const std::string& name : known) {
    if (leading_word(name).word != first.word) continue;
    if (!found.empty()) return "";
    found = name;
  }
  return found;
}

}  // namespace

std::string nearest_name(std::string_view typed, const std::vector<std::string>& known) {
  std::string nearest;
  std::size_t best = std::string::npos;
  for (const std::string& name : known) {
    const std::size_t distance = edit_distance(typed, name);
    if (distance < best) {
      best = distance;
      nearest = name;
    }
  }
  if (nearest.empty() || best > std::max<std::size_t>(2, nearest.size() / 3))
    return only_name_sharing_first_word(typed, known);
  return nearest;
}

}  // namespace rover::io
