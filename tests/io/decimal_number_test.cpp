// Decimal numbers as data files and flags write them (io/decimal_number.hpp).
#include "io/decimal_number.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace rover::io {
namespace {

TEST(DecimalNumber, ReadsWhatJsonAndCsvWritersWrite) {
  EXPECT_EQ(parse_decimal_number("0.25").value, 0.25);
  EXPECT_EQ(parse_decimal_number("+2.5e-1").value, 0.25);
  EXPECT_EQ(parse_decimal_number("-.5").value, -0.5);
  EXPECT_EQ(parse_decimal_number("1E3").value, 1000.0);
  // The largest and smallest normal doubles round-trip.
  EXPECT_EQ(parse_decimal_number("1.7976931348623157e308").value, std::numeric_limits<double>::max());
  EXPECT_EQ(parse_decimal_number("2.2250738585072014e-308").value, std::numeric_limits<double>::min());
}

TEST(DecimalNumber, RefusesOtherNotationsWithTheirReason) {
  for (const char* text : {"", "+", "0x1p-3", "0X10", "1.5x", "0,2", " 1", "1 ", "++1", "+-1", "1e", "abc"})
    EXPECT_EQ(parse_decimal_number(text).status, DecimalStatus::kNotANumber) << text;
  for (const char* text : {"inf", "-inf", "nan", "infinity"})
    EXPECT_EQ(parse_decimal_number(text).status, DecimalStatus::kNotFinite) << text;
  for (const char* text : {"1e400", "-1e999"})
    EXPECT_EQ(parse_decimal_number(text).status, DecimalStatus::kOutOfRange) << text;
  EXPECT_NE(decimal_number_hint("0x1p-3").find("hexadecimal"), std::string::npos);
  EXPECT_NE(decimal_number_hint("-0X10").find("hexadecimal"), std::string::npos);
  EXPECT_EQ(decimal_number_hint("1.5x"), "");  // a typo, not hexadecimal
  EXPECT_NE(decimal_number_hint("0,2").find("write a point (0.2)"), std::string::npos);
  EXPECT_EQ(decimal_number_hint("a,b"), "");
}

}  // namespace
}  // namespace rover::io
