// Scaling by powers of two: exact (barring overflow and subnormals), so that a quantity brought
// near a unit size this way keeps every bit of every ratio. Eigen and std only.
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace shellcontract {

/// The e with x = m 2^e, |m| in [0.5, 1) (std::frexp); 0 for 0.
inline int binary_exponent(double x) {
  int e = 0;
  std::frexp(x, &e);
  return e;
}

/// x * 2^k entry by entry, exactly (std::ldexp).
template <class Derived>
auto times_power_of_two(const Eigen::MatrixBase<Derived>& x, int k) {
  return x.unaryExpr([k](double v) { return std::ldexp(v, k); }).eval();
}

}  // namespace shellcontract
