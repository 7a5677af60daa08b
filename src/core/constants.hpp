// Mathematical constants used by more than one module. C++17 has no std::numbers; EIGEN_PI is a
// long double, which would promote the double arithmetic around it and change its rounding.
#pragma once

namespace shellcontract {

/// pi, rounded to the nearest double.
inline constexpr double PI = 3.14159265358979323846;

}  // namespace shellcontract
