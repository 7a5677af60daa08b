// A number given as text on a command line or in a keyframe list: decimal only, the whole text.
// std::strtod, which these options were read with, also skips leading blanks (so " 3" passed and
// "3 " did not), reads hexadecimal ("0x3" was 3) and depends on the C locale's decimal point; the
// integers beside them (std::from_chars) took none of that, nor a leading '+'. Mesh files keep
// strtod's reading (src/mesh/off_number.hpp): files written by other programs may use any form it
// accepts.
#pragma once

#include <cctype>
#include <charconv>
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

}  // namespace shellcontract
