// See text_encoding.hpp.
#include "io/text_encoding.hpp"

#include <algorithm>
#include <cstdio>

namespace rover::io {
namespace {

// A NUL byte among a text's first 4 bytes: UTF-16 or UTF-32 without a byte-order mark.
constexpr std::size_t kEncodingProbeBytes = 4;
constexpr std::ptrdiff_t kWideTextProbeNuls = 2;

// One UTF-8 character's first byte: its length and the range its second
// byte must lie in (RFC 3629, section 4), which excludes overlong forms,
// surrogates and code points beyond U+10FFFF.
struct Utf8Lead {
  std::size_t length = 0;  // 0: no lead byte
  unsigned char second_min = 0x80, second_max = 0xBF;
};

Utf8Lead utf8_lead(unsigned char byte) {
  if (byte < 0x80) return {1};
  if (byte >= 0xC2 && byte <= 0xDF) return {2};
  if (byte == 0xE0) return {3, 0xA0, 0xBF};
  if (byte == 0xED) return {3, 0x80, 0x9F};
  if (byte >= 0xE1 && byte <= 0xEF) return {3};
  if (byte == 0xF0) return {4, 0x90, 0xBF};
  if (byte == 0xF4) return {4, 0x80, 0x8F};
  if (byte >= 0xF1 && byte <= 0xF3) return {4};
  return {0};
}

// The bytes of the character whose first byte is at `offset` that are well
// formed: its length when the whole character is.
std::size_t utf8_valid_prefix(std::string_view text, std::size_t offset) {
  const Utf8Lead lead = utf8_lead(static_cast<unsigned char>(text[offset]));
  if (lead.length <= 1) return lead.length;
  for (std::size_t k = 1; k < lead.length; ++k) {
    if (offset + k >= text.size()) return k;
    const auto byte = static_cast<unsigned char>(text[offset + k]);
    const unsigned char min = k == 1 ? lead.second_min : 0x80, max = k == 1 ? lead.second_max : 0xBF;
    if (byte < min || byte > max) return k;
  }
  return lead.length;
}

std::string hex_byte(char byte) {
  char text[8];
  std::snprintf(text, sizeof text, "0x%02X", static_cast<unsigned>(static_cast<unsigned char>(byte)));
  return text;
}

}  // namespace

std::size_t invalid_utf8_offset(std::string_view text) {
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t length = utf8_lead(static_cast<unsigned char>(text[i])).length;
    if (length == 0 || utf8_valid_prefix(text, i) != length) return i;
    i += length;
  }
  return std::string_view::npos;
}

std::string invalid_utf8_description(std::string_view text, std::size_t offset) {
  const std::size_t length = utf8_lead(static_cast<unsigned char>(text[offset])).length;
  const std::string byte = "byte " + hex_byte(text[offset]);
  if (length == 0) return byte + " begins no UTF-8 character";
  const std::size_t next = offset + utf8_valid_prefix(text, offset);
  const std::string begins = byte + " begins a " + std::to_string(length) + "-byte UTF-8 character, but ";
  if (next >= text.size()) return begins + "the file ends before it does";
  return begins + "byte " + hex_byte(text[next]) + " does not continue it";
}

std::string text_encoding_problem(std::string_view text) {
  using namespace std::string_view_literals;
  if (text.starts_with("\x00\x00\xFE\xFF"sv) || text.starts_with("\xFF\xFE\x00\x00"sv)) return "is UTF-32 text";
  if (text.starts_with("\xFE\xFF"sv) || text.starts_with("\xFF\xFE"sv)) return "is UTF-16 text";
  // Binary files rover writes, by their signatures (no NUL in the first line).
  if (text.starts_with("\x89HDF"sv)) return "is an HDF5 file, not text (a result file? give its CSV)";
  if (text.starts_with("\x89PNG"sv)) return "is a PNG image, not text";
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
