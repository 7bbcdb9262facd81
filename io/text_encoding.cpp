// See text_encoding.hpp.
#include "io/text_encoding.hpp"

#include <algorithm>

namespace rover::io {
namespace {

// A NUL byte among a text's first 4 bytes: UTF-16 or UTF-32 without a byte-order mark.
constexpr std::size_t kEncodingProbeBytes = 4;
constexpr std::ptrdiff_t kWideTextProbeNuls = 2;

}  // namespace

std::string text_encoding_problem(std::string_view text) {
  using namespace std::string_view_literals;
  if (text.starts_with("\x00\x00\xFE\xFF"sv) || text.starts_with("\xFF\xFE\x00\x00"sv)) return "is UTF-32 text";
  if (text.starts_with("\xFE\xFF"sv) || text.starts_with("\xFF\xFE"sv)) return "is UTF-16 text";
  const std::size_t nul = text.find('\0');
  if (nul == std::string_view::npos) return "";
  // UTF-16 or UTF-32 text of ASCII characters has a NUL in every other byte or more.
  const std::string_view probe = text.substr(0, kEncodingProbeBytes);
  if (std::count(probe.begin(), probe.end(), '\0') >= kWideTextProbeNuls)
    return "holds NUL bytes from its first characters on (UTF-16 or UTF-32 text?)";
  return "holds a NUL byte (a binary file?)";
}

std::string line_ending_problem(std::string_view line) {
  const std::size_t cr = line.find('\r');
  if (cr == std::string_view::npos || cr + 1 == line.size()) return "";
  return "its lines end in a carriage return alone (CR, as classic Mac OS and some data loggers write): save it "
         "with LF or CRLF line ends";
}

}  // namespace rover::io
