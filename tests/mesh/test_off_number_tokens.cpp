// The numbers of mesh and text files (src/core/decimal_text.hpp, parse_c_number; the OFF and OBJ
// scans' coordinates among them): every token must give the double strtod gives in the "C"
// locale (this test's), bit for bit, and be refused exactly when strtod would not read all of it.
// Tokens with many digits (halfway cases), exponents, denormals, a leading '+', inf, nan,
// hexadecimal and junk, and random doubles printed at 17 digits. Checked to fail when a token
// from_chars does not read in full is refused instead of read as strtod reads it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "core/decimal_text.hpp"

namespace shellcontract {
namespace {

/// strtod's verdict on the whole token: read in full, and its value.
bool strtod_reads(const std::string& token, double& value) {
  char* end = nullptr;
  value = std::strtod(token.c_str(), &end);
  return end == token.c_str() + token.size();
}

void expect_as_strtod(const std::string& token) {
  double expected = 0.0, got = -123.0;
  const bool reads = strtod_reads(token, expected);
  ASSERT_EQ(parse_c_number(token, got), reads) << "'" << token << "'";
  if (reads && std::isnan(expected)) {
    // A NaN's sign only: glibc's strtod puts nan(123)'s digits into the payload, which no reader
    // keeps (each refuses a coordinate that is not finite).
    EXPECT_TRUE(std::isnan(got)) << "'" << token << "': " << got;
    EXPECT_EQ(std::signbit(got), std::signbit(expected)) << "'" << token << "'";
  } else if (reads) {
    EXPECT_EQ(std::memcmp(&got, &expected, sizeof got), 0) << "'" << token << "': " << got << " vs " << expected;
  }
}

TEST(OffNumberTokens, TrickyTokensGiveStrtodsBits) {
  const std::vector<std::string> tokens = {
      "0", "-0", "+0", "0.0", "-0.0", "1", "-1", "+1", "+1.5e3", "1.", ".5", "-.5", "5e-1", "5E+1", "1e308", "1.7976931348623157e308",
      "1.7976931348623159e308", "1e309", "-1e309", "2.2250738585072014e-308", "2.2250738585072011e-308",
      "4.9406564584124654e-324", "2.4703282292062328e-324", "2.4703282292062327e-324", "1e-320", "-1e-320", "1e-400",
      "-1e-400", "0.1", "0.30000000000000004", "9007199254740993", "9007199254740992.5",
      "1.00000000000000011102230246251565404236316680908203125",
      "1.000000000000000111022302462515654042363166809082031250000001",
      "123456789012345678901234567890123456789012345678901234567890e-40", "0000000000000000000000001.25",
      "3.14159265358979323846264338327950288419716939937510582097494459", "inf", "-inf", "INF", "infinity", "+inf",
      "nan", "-nan", "NaN", "nan(123)", "0x1p3", "0X1.8P1", "-0x10", "1e", "1e+", "e5", ".", "-", "+", "+-1", "1.2.3",
      "12abc", "1,5", "--1", "1e5x", "0x", "1d5", "0e0", "00.00e-00",
      // strtod's own forms beyond from_chars' (a sign before hexadecimal, inf or nan; blanks
      // before the number; out of range without an exponent), and what it stops short of.
      " 1.5", "\t-2", "\n+0x1p-2", "-0x.8", "+0x1P+1", "0x1p99999", "-0x1p-99999", "0x1.", "0xg",
      "0x+1", "0x-1", "0xinf", "0xp1", "+nan", "-NAN(1)", "+infinity", "-Infinity", "+-inf", "-+1",
      "1e99999999999999999999999", "-1e-99999999999999999999", "1" + std::string(400, '0'),
      "0." + std::string(400, '0') + "1", "-0." + std::string(400, '0') + "1e+5", "0.0001e-305",
      "1000e305", "1 ", "1e5 ", "nan(1 2)", "0x1p3x", "1.5,0", "1,0"};
  for (const std::string& t : tokens) expect_as_strtod(t);
}

TEST(OffNumberTokens, RandomDoublesAtSeventeenDigitsGiveStrtodsBits) {
  std::mt19937_64 rng(20261203u);
  char buf[64];
  for (int i = 0; i < 20000; ++i) {
    std::uint64_t bits = rng();
    double d = 0.0;
    std::memcpy(&d, &bits, sizeof d);
    if (!std::isfinite(d)) continue;
    for (const char* format : {"%.17g", "%.16g", "%.6g", "%.25e"}) {
      std::snprintf(buf, sizeof buf, format, d);
      expect_as_strtod(buf);
    }
  }
}

TEST(OffNumberTokens, ReadsOnlyTheTokenNotWhatFollowsIt) {
  // A view into "1.5e3 7": the token "1.5" must not take the "e3" after it.
  const std::string line = "1.5e3 7";
  double v = 0.0;
  ASSERT_TRUE(parse_c_number(std::string_view(line).substr(0, 3), v));
  EXPECT_EQ(v, 1.5);
  // "+2" is strtod's, not from_chars': still read.
  ASSERT_TRUE(parse_c_number(std::string_view("+2 x").substr(0, 2), v));
  EXPECT_EQ(v, 2.0);
}

}  // namespace
}  // namespace shellcontract
