// The AVX2 dihedral kernel's atan2 (batch_atan2, src/pbd/batch_lanes.hpp): within a few ulp of
// std::atan2 everywhere, with std::atan2's signs, octants and signed zeros, because the kernel's
// angle difference theta - theta_bar (and so every hinge step) inherits its error. A wrong
// coefficient or octant shows far over the bound (checked: one P coefficient changed by 1e-6
// relative fails both accuracy tests and the dihedral batches' test).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "pbd/constraint_batches.hpp"

namespace shellcontract {
namespace {

/// |a - b| in units in the last place of b (b finite).
double ulps(double a, double b) {
  const double spacing = std::nextafter(std::abs(b), std::numeric_limits<double>::infinity()) - std::abs(b);
  return std::abs(a - b) / spacing;
}

/// The worst error over pairs (y, x), and it must not exceed `bound` ulps.
void expect_close_to_libm(const std::vector<double>& y, const std::vector<double>& x, double bound) {
  std::vector<double> theta(y.size());
  if (!batch_atan2(y.data(), x.data(), theta.data(), y.size())) GTEST_SKIP() << "no AVX2 on this CPU";
  double worst = 0.0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double ref = std::atan2(y[i], x[i]);
    const double e = ulps(theta[i], ref);
    worst = std::max(worst, e);
    EXPECT_LE(e, bound) << "atan2(" << y[i] << ", " << x[i] << ") = " << theta[i] << ", libm " << ref;
  }
  ::testing::Test::RecordProperty("worst_ulps", std::to_string(worst));
}

TEST(LaneAtan2, WithinFourUlpOfLibmOverEveryOctantAndScale) {
  std::mt19937 rng(58);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-40, 40);
  std::vector<double> y, x;
  for (int i = 0; i < 200000; ++i) {
    const double s = std::ldexp(1.0, exponent(rng));
    y.push_back(s * unit(rng));
    // Same scale for both half of the time (every ratio near 1), else independent scales.
    x.push_back((i % 2 ? s : std::ldexp(1.0, exponent(rng))) * unit(rng));
  }
  expect_close_to_libm(y, x, 4.0);
}

TEST(LaneAtan2, ReductionBoundariesAndAxes) {
  // Ratios at the reduction's switch (0.66), at 1 (the octant swap), tiny and huge ratios, the
  // axes and the angles near +-pi (a hinge almost folded flat onto itself).
  std::vector<double> y, x;
  for (double r : {0.0, 1e-300, 1e-17, 1e-8, 0.4142135623730950, 0.65999999999999, 0.66,
                   0.66000000000001, 0.9999999999999999, 1.0, 1.0000000000000002, 1.5151515,
                   2.414213562373095, 1e8, 1e17})
    for (double sy : {1.0, -1.0})
      for (double sx : {1.0, -1.0}) {
        y.push_back(sy * r);
        x.push_back(sx * 1.0);
        y.push_back(sy * 1.0);
        x.push_back(sx * r);
      }
  expect_close_to_libm(y, x, 4.0);
}

TEST(LaneAtan2, SignedZerosAsLibm) {
  const std::vector<double> y = {0.0, -0.0, 0.0, -0.0, 0.0, -0.0, 1.0, -1.0};
  const std::vector<double> x = {0.0, 0.0, -0.0, -0.0, -2.0, -2.0, -0.0, 0.0};
  std::vector<double> theta(y.size());
  if (!batch_atan2(y.data(), x.data(), theta.data(), y.size())) GTEST_SKIP() << "no AVX2 on this CPU";
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double ref = std::atan2(y[i], x[i]);
    EXPECT_EQ(theta[i], ref) << "atan2(" << y[i] << ", " << x[i] << ")";
    EXPECT_EQ(std::signbit(theta[i]), std::signbit(ref)) << "atan2(" << y[i] << ", " << x[i] << ")";
  }
}

}  // namespace
}  // namespace shellcontract
