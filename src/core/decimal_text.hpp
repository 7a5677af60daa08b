// Numbers read from text, whatever locale a host program has set. The library is also a Python
// module, and the process it runs in may have set LC_NUMERIC to a decimal-comma locale (PyQt and
// GTK front ends do, from the desktop's language); std::strtod, std::atof, sscanf and printf
// follow it, so "0.5" stopped at the point there and "1,0" was read as one. std::from_chars and
// std::to_chars take no locale: every number the library reads from a file or an option goes
// through one of the two parsers here.
//
// parse_decimal: a number given as text on a command line or in a keyframe list, decimal only,
// the whole text. std::strtod, which these options were read with, also skips leading blanks (so
// " 3" passed and "3 " did not), reads hexadecimal ("0x3" was 3); the integers beside them
// (std::from_chars) took none of that, nor a leading '+'.
//
// parse_c_number: a number in a file, in every form std::strtod reads in the "C" locale: files
// written by other programs may use any of them, and each reader keeps what it accepted.
//
// fixed_text, general_text: printf's "%.Nf" and "%.Ng" for messages, as the "C" locale writes
// them (the shortest round-trip text is shortest_text, shellcontract/options.hpp).
#pragma once

#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <string>
#include <string_view>
#include <system_error>

namespace shellcontract {

/// True, with the value, when `text` is exactly one decimal number: an optional sign, digits with
/// an optional point (at least one digit), an optional exponent; no blanks, no hexadecimal, no inf
/// or nan (std::from_chars's general format, locale-independent, plus a leading '+').
inline bool parse_decimal(std::string_view text, double& value) {
  // One sign: from_chars takes '-' itself; a '+' is dropped here (so "+-3" is not a number).
  const bool plus = !text.empty() && text.front() == '+';
  if (plus) text.remove_prefix(1);
  const std::string_view digits =
      !plus && !text.empty() && text.front() == '-' ? text.substr(1) : text;
  // from_chars also reads "inf", "nan" and "0x..." would stop after the 0: only a digit or a
  // point may start the number.
  if (digits.empty() ||
      !(std::isdigit(static_cast<unsigned char>(digits.front())) || digits.front() == '.'))
    return false;
  double x = 0.0;
  const auto r =
      std::from_chars(text.data(), text.data() + text.size(), x, std::chars_format::general);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size()) return false;
  value = x;
  return true;
}

/// True, with the value, when `text` is exactly one decimal integer that fits a long: an optional
/// sign and digits, nothing else (so "+3" as parse_decimal takes it, "3.0" and " 3" not).
inline bool parse_decimal_integer(std::string_view text, long& value) {
  if (text.size() > 1 && text.front() == '+' && text[1] != '-') text.remove_prefix(1);
  long x = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), x);
  if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size()) return false;
  value = x;
  return true;
}

namespace decimal_text_detail {

/// For a number that std::from_chars found out of a double's range: true when it is too large
/// (strtod gives +-HUGE_VAL), false when too small (strtod gives 0). `text` is the digits, an
/// optional point and the exponent (after 'e', or 'p' for hexadecimal, a power of two) that
/// from_chars read; the first nonzero digit's place plus the exponent has the sign of the
/// magnitude's logarithm, which is far from 0 for a number out of range.
inline bool overflows(std::string_view text, bool hex) {
  const char mark = hex ? 'p' : 'e';
  bool seen_point = false, seen_digit = false;
  long long before_point = 0, leading_zeros_after_point = 0;
  std::size_t i = 0;
  for (; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '.') {
      seen_point = true;
      continue;
    }
    if (c == mark || c == (mark - 'a' + 'A')) break;
    const bool zero = c == '0';
    if (!seen_digit && zero) {
      if (seen_point) ++leading_zeros_after_point;
      continue;
    }
    seen_digit = true;
    if (!seen_point) ++before_point;
  }
  // The first nonzero digit's power of the base (10, or 16 for hexadecimal).
  const long long place = before_point > 0 ? before_point - 1 : -(leading_zeros_after_point + 1);
  long long exponent = 0;
  bool negative = false;
  if (++i < text.size() && (text[i] == '+' || text[i] == '-')) negative = text[i++] == '-';
  for (; i < text.size(); ++i)  // digits only (from_chars read them); saturated
    if (exponent < 1000000000000LL) exponent = exponent * 10 + (text[i] - '0');
  const long long log = (hex ? 4 * place : place) + (negative ? -exponent : exponent);
  return log >= 0;
}

/// parse_c_number after its sign: a hexadecimal or decimal number (or inf, nan), all of `text`.
inline bool parse_unsigned_c_number(std::string_view text, double& value) {
  const bool hex = text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X');
  if (hex) {
    text.remove_prefix(2);
    // from_chars would take "inf" or "nan" here too; strtod reads "0x" then a digit or a point.
    if (!(std::isxdigit(static_cast<unsigned char>(text.front())) || text.front() == '.'))
      return false;
  } else if (!text.empty() && (text.front() == '+' || text.front() == '-')) {
    return false;  // one sign only (from_chars would take a '-' after a '+')
  }
  double x = 0.0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), x,
                                 hex ? std::chars_format::hex : std::chars_format::general);
  if (r.ptr != text.data() + text.size()) return false;
  if (r.ec == std::errc::result_out_of_range)
    x = overflows(text, hex) ? std::numeric_limits<double>::infinity() : 0.0;
  else if (r.ec != std::errc())
    return false;
  value = x;
  return true;
}

}  // namespace decimal_text_detail

/// True, with the value, when all of `token` is one number as std::strtod reads it in the "C"
/// locale, with strtod's double bit for bit: leading blanks (isspace of the "C" locale), a sign
/// ('+' too), decimal with an optional exponent, hexadecimal ("0x1.8p3"), inf, infinity, nan,
/// nan(chars), any case; too large a number is +-infinity and too small one +-0, as strtod
/// gives them. Never a decimal comma, whatever the locale. std::from_chars reads the common
/// tokens in one call (the OFF scan's speed rests on it: lab/regions/speed.md).
inline bool parse_c_number(std::string_view token, double& value) {
  const char* const first = token.data();
  const char* const last = first + token.size();
  double fast = 0.0;
  const auto r = std::from_chars(first, last, fast, std::chars_format::general);
  if (r.ec == std::errc() && r.ptr == last) {
    value = fast;
    return true;
  }
  while (!token.empty() &&
         (token.front() == ' ' || (token.front() >= '\t' && token.front() <= '\r')))
    token.remove_prefix(1);
  const bool negative = !token.empty() && token.front() == '-';
  if (!token.empty() && (token.front() == '+' || negative)) token.remove_prefix(1);
  double x = 0.0;
  if (token.empty() || !decimal_text_detail::parse_unsigned_c_number(token, x)) return false;
  value = negative ? -x : x;
  return true;
}

/// printf("%.<digits>f", x) in the "C" locale: std::to_chars with a format and a precision
/// writes printf's characters, with no locale.
inline std::string fixed_text(double x, int digits) {
  char buf[400];  // DBL_MAX has 309 digits before the point
  const auto r = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::fixed, digits);
  return r.ec == std::errc() ? std::string(buf, r.ptr) : std::string("?");
}

/// printf("%.<digits>g", x) in the "C" locale (std::to_chars, as fixed_text).
inline std::string general_text(double x, int digits) {
  char buf[400];
  const auto r = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::general, digits);
  return r.ec == std::errc() ? std::string(buf, r.ptr) : std::string("?");
}

}  // namespace shellcontract
