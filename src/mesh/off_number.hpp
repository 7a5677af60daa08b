// The OFF scan's reading of a number (src/mesh/off_scan.cpp), apart from off_scan.hpp so that its
// tests reach it without every reader of that header depending on it.
#pragma once

#include <string_view>

namespace shellcontract {

/// A vertex line's number as strtod reads it: true when strtod would read the whole token (any
/// form it accepts: a sign, an exponent, inf, nan, hexadecimal), with strtod's value in value.
/// std::from_chars reads the common tokens (the same correctly rounded double, several times
/// faster: lab/regions/speed.md); whatever it does not read in full to a finite value (a leading
/// '+', an underflow, inf, nan, hexadecimal, junk) goes to strtod itself.
bool parse_off_number(std::string_view token, double& value);

}  // namespace shellcontract
