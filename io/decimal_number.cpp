// See decimal_number.hpp.
#include "io/decimal_number.hpp"

#include <charconv>
#include <cmath>
#include <system_error>

namespace rover::io {

DecimalNumber parse_decimal_number(std::string_view text) {
  // from_chars does not take a leading '+', and reads no hexadecimal in its
  // general format.
  const std::string_view digits = !text.empty() && text.front() == '+' ? text.substr(1) : text;
  if (digits.empty() || digits.front() == '+' || (digits.front() == '-' && text.front() == '+')) return {};
  double value = 0.0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (end != digits.data() + digits.size()) return {};
  if (error == std::errc::result_out_of_range) return {0.0, DecimalStatus::kOutOfRange};
  if (error != std::errc()) return {};
  if (!std::isfinite(value)) return {0.0, DecimalStatus::kNotFinite};
  return {value, DecimalStatus::kOk};
}

bool is_hexadecimal_number(std::string_view text) {
  const std::string_view unsigned_text = !text.empty() && (text.front() == '+' || text.front() == '-') ? text.substr(1) : text;
  return unsigned_text.starts_with("0x") || unsigned_text.starts_with("0X");
}

std::string decimal_number_hint(std::string_view text) {
  if (is_hexadecimal_number(text))
    return "hexadecimal is not read: write the number in decimal digits (0.125, not 0x1p-3)";
  if (const std::size_t comma = text.find(','); comma != std::string_view::npos &&
      parse_decimal_number(std::string(text.substr(0, comma)) + "." + std::string(text.substr(comma + 1))).status ==
          DecimalStatus::kOk)
    return "a decimal comma? write a point (" + std::string(text.substr(0, comma)) + "." +
           std::string(text.substr(comma + 1)) + ")";
  return "";
}

}  // namespace rover::io
