// Numbers as text files and the command line write them: decimal digits with
// an optional sign, point and exponent ("0.25", "+2.5e-1", ".5"). Hexadecimal
// ("0x1p-3"), which C's strtod would read but no JSON config can hold, and a
// decimal comma are refused with a hint; "inf" and "nan" read as not finite.
#pragma once

#include <string>
#include <string_view>

namespace rover::io {

enum class DecimalStatus {
  kOk,
  kNotANumber,   // no decimal number: "abc", "0x10", "0,2", " 1"
  kNotFinite,    // "inf", "-inf", "nan"
  kOutOfRange,   // beyond double's range or below its smallest subnormal: "1e999", "1e-400"
};

struct DecimalNumber {
  double value = 0.0;  // finite only when status is kOk
  DecimalStatus status = DecimalStatus::kNotANumber;
};

// `text` read whole as a finite decimal number, or why it is none.
DecimalNumber parse_decimal_number(std::string_view text);

// Whether `text` is written as C's hexadecimal numbers are ("0x10", "-0X1p-3").
bool is_hexadecimal_number(std::string_view text);

// Why `text` is no decimal number when it looks like one written another
// way ("hexadecimal is not read", "a decimal comma?"), else empty.
std::string decimal_number_hint(std::string_view text);

}  // namespace rover::io
