// Rotation-variant polar decomposition, I4 closed form and the robust sign (math-spec 5, 13).
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cmath>

#include "material/polar2.hpp"
#include "material_cases.hpp"
#include "support/fd_check.hpp"

namespace shellcontract {
namespace {

using test::FCase;
using test::matrix_string;

/// Independent rotation-variant SVD (Kim et al. 2019 / HOBAK): F = U Sigma V^T with U, V proper
/// rotations and the reflection, if any, on the smallest singular value. Returns R = U V^T.
Mat2 rotation_variant_svd_R(const Mat2& F) {
  Eigen::JacobiSVD<Mat2> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat2 U = svd.matrixU();
  Mat2 V = svd.matrixV();
  if (U.determinant() < 0.0) U.col(1) *= -1.0;  // move the reflection into Sigma_22
  if (V.determinant() < 0.0) V.col(1) *= -1.0;
  return U * V.transpose();
}

TEST(Polar2, RotationIsProperAndStretchSymmetricWithSpecIdentities) {
  for (const FCase& c : test::material_cases()) {
    SCOPED_TRACE(c.describe());
    const Polar2 pd = polar2(c.F);
    ASSERT_FALSE(pd.degenerate);
    const Mat2 S = pd.R.transpose() * c.F;
    EXPECT_LE((pd.R.transpose() * pd.R - Mat2::Identity()).norm(), 1e-14);
    EXPECT_NEAR(pd.R.determinant(), 1.0, 1e-14);  // never a reflection, even when det F < 0
    EXPECT_NEAR(S(0, 1), S(1, 0), 1e-14 * (1.0 + c.F.norm()));
    EXPECT_NEAR(S.trace(), pd.rho, 1e-14 * (1.0 + c.F.norm()));
    EXPECT_NEAR(S.determinant(), c.F.determinant(), 1e-14 * (1.0 + c.F.squaredNorm()));
    const double trC = c.F.squaredNorm();
    EXPECT_NEAR(pd.rho * pd.rho, trC + 2.0 * c.F.determinant(), 1e-13 * (1.0 + trC));
  }
}

TEST(Polar2, MatchesIndependentRotationVariantSvd) {
  int compared = 0;
  for (const FCase& c : test::material_cases()) {
    Eigen::JacobiSVD<Mat2> svd(c.F);
    const Vec2 s = svd.singularValues();
    if (s(0) - s(1) < 1e-3 * s(0)) continue;  // R is unique only for distinct singular values
    SCOPED_TRACE(c.describe());
    EXPECT_LE((polar2(c.F).R - rotation_variant_svd_R(c.F)).norm(), 1e-12);
    ++compared;
  }
  EXPECT_GE(compared, 90);
}

TEST(Polar2, GuardGivesIdentityOnTheSymmetricTracelessFamily) {
  // rho = 0 exactly for F = [[u, v], [v, -u]] (math-spec 5), and F = 0; R = I, no NaN.
  for (const auto& uv : {Vec2(0.3, -1.2), Vec2(2.0, 0.0), Vec2(0.0, 1e-8), Vec2(0.0, 0.0)}) {
    Mat2 F;
    F << uv(0), uv(1), uv(1), -uv(0);
    SCOPED_TRACE("F = " + matrix_string(F));
    const Polar2 pd = polar2(F);
    EXPECT_TRUE(pd.degenerate);
    EXPECT_EQ(pd.R, Mat2::Identity());
    EXPECT_EQ(pd.rho, 0.0);
    const Vec2 a(0.6, 0.8);
    EXPECT_TRUE(std::isfinite(fiber_i4(F, a)));
    EXPECT_DOUBLE_EQ(fiber_i4(F, a), a.dot(F * a));  // S = F for R = I
  }
  // Just above the guard the rotation is computed and proper.
  Mat2 F;
  F << 1.0 + 1e-9, 0.5, 0.5, -1.0;  // rho = 1e-9 > 1e-12 |F|
  const Polar2 pd = polar2(F);
  EXPECT_FALSE(pd.degenerate) << "F = " << matrix_string(F);
  EXPECT_NEAR(pd.R.determinant(), 1.0, 1e-12);
  EXPECT_NEAR(pd.R(0, 0), 1.0, 1e-6);  // c = 1e-9, d = 0: R = I by the formula, not the guard
}

TEST(FiberInvariants, I4ClosedFormMatchesExplicitStretchOnBothDeterminantSigns) {
  int positive = 0, negative = 0;
  for (const FCase& c : test::material_cases()) {
    SCOPED_TRACE(c.describe());
    const Polar2 pd = polar2(c.F);
    const double explicit_i4 = c.a.dot(pd.R.transpose() * c.F * c.a);  // a^T (R^T F) a
    EXPECT_NEAR(fiber_i4(c.F, c.a), explicit_i4, 1e-12 * (1.0 + c.F.squaredNorm()));
    EXPECT_DOUBLE_EQ(fiber_i5(c.F, c.a), (c.F * c.a).squaredNorm());
    (c.F.determinant() > 0.0 ? positive : negative)++;
  }
  EXPECT_GE(positive, 20);
  EXPECT_GE(negative, 20);
}

TEST(FiberInvariants, RobustSignEqualsSignOfI4AwayFromTies) {
  int minus = 0;
  for (const FCase& c : test::material_cases()) {
    SCOPED_TRACE(c.describe());
    const double i4 = fiber_i4(c.F, c.a);
    if (std::abs(i4) < 1e-9) continue;
    EXPECT_EQ(fiber_sign(c.F, c.a), i4 > 0.0 ? 1.0 : -1.0) << "I4 = " << i4;
    if (i4 < 0.0) ++minus;
  }
  EXPECT_GE(minus, 5) << "the case list must exercise sigma = -1";
}

TEST(FiberInvariants, InversionCasesOfMathSpec13) {
  const Vec2 a(1.0, 0.0);
  // diag(-0.5, 1): I4 = -0.5, sigma = -1.
  Mat2 F = Vec2(-0.5, 1.0).asDiagonal();
  EXPECT_NEAR(fiber_i4(F, a), -0.5, 1e-15);
  EXPECT_EQ(fiber_sign(F, a), -1.0);
  // diag(-2, 1): the reflection goes to the other axis, I4 = +2, sigma = +1.
  F = Vec2(-2.0, 1.0).asDiagonal();
  EXPECT_NEAR(fiber_i4(F, a), 2.0, 1e-15);
  EXPECT_EQ(fiber_sign(F, a), 1.0);
  EXPECT_LE((polar2(F).R + Mat2::Identity()).norm(), 1e-15) << "R = rotation by pi";
}

TEST(FiberInvariants, TieRuleGivesPlusOne) {
  // F = diag(-2, 0.5), a = (sqrt(0.2), sqrt(0.8)): I5 = 4 * 0.2 + 0.25 * 0.8 = 1 = -det F.
  const Mat2 F = Vec2(-2.0, 0.5).asDiagonal();
  const Vec2 a(std::sqrt(0.2), std::sqrt(0.8));
  SCOPED_TRACE("F = " + matrix_string(F) + ", a = " + matrix_string(a));
  ASSERT_LE(std::abs(fiber_i5(F, a) + F.determinant()), 1e-15);
  EXPECT_EQ(fiber_sign(F, a), 1.0);
  // Off the tie on either side the sign follows I5 + det F.
  EXPECT_EQ(fiber_sign(Mat2(Vec2(-2.0, 0.5 - 1e-6).asDiagonal()), a), 1.0);  // det up: I5 + det > 0
  EXPECT_EQ(fiber_sign(Mat2(Vec2(-2.0, 0.5 + 1e-6).asDiagonal()), a), -1.0);  // I5 + det < 0
  // F = 0: I5 = det = 0 is a tie as well.
  EXPECT_EQ(fiber_sign(Mat2::Zero(), a), 1.0);
}

TEST(FiberInvariants, SignIsPlusOneWheneverDetIsPositive) {
  // Default orientation s = +1 gives det Fbar > 0 and hence sigma = +1 (math-spec 5).
  for (const FCase& c : test::material_cases()) {
    if (c.F.determinant() <= 0.0) continue;
    SCOPED_TRACE(c.describe());
    EXPECT_EQ(fiber_sign(c.F, c.a), 1.0);
  }
}

}  // namespace
}  // namespace shellcontract
