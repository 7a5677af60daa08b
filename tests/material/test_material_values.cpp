// Model-specific checks with known answers: the closed forms of math-spec 13, the inversion
// case of anisotropic ARAP, ARAP vs Sqrt, the C-form P3 = F S (math-spec 4.4), small-strain
// agreement with linear elasticity, and every guard (Mooney-Rivlin |J| clamp, fibre |F a| -> 0,
// polar rho -> 0, active-fibre gamma range).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "fem/triangle_element.hpp"
#include "material/active_fiber.hpp"
#include "material/anisotropic_arap.hpp"
#include "material/anisotropic_sqrt.hpp"
#include "material/anisotropic_stvk.hpp"
#include "material/corotated.hpp"
#include "material/linear.hpp"
#include "material/mooney_rivlin.hpp"
#include "material/stvk.hpp"
#include "material_cases.hpp"
#include "shellcontract/error.hpp"
#include "support/fd_check.hpp"

namespace shellcontract {
namespace {

using test::FCase;
using test::matrix_string;

const MaterialParams PARAMS = test::test_params();
const ElementMaterialData FIBER_X{Vec2(1.0, 0.0)};

// ------------------------------------------------------------ closed forms (math-spec 13)

// Fbar = diag(varsigma, 1), a = (1, 0). Expected psi from math-spec 13 and P11 = d psi / d
// varsigma (the derivative of that closed form, written out by hand), P12 = P21 = 0.
TEST(ClosedForm, UniaxialStretchValuesOfMathSpec13) {
  const double mu = PARAMS.mu, lam = PARAMS.lambda, c10 = PARAMS.c10, c01 = PARAMS.c01;
  const double muA = PARAMS.mu_aniso, g = PARAMS.fiber_target;
  const Stvk stvk(PARAMS);
  const Corotated corot(PARAMS);
  const Linear linear(PARAMS);
  const MooneyRivlin mr(PARAMS);
  const AnisotropicArap arap(PARAMS);
  const AnisotropicSqrt sq(PARAMS);
  const AnisotropicStvk astvk(PARAMS);
  const ActiveFiber active(PARAMS);
  struct Row {
    const MembraneMaterial* m;
    std::function<double(double)> psi, p11;
  };
  const std::vector<Row> rows{
      {&stvk, [&](double s) { return (mu + lam / 2) * (s * s - 1) * (s * s - 1) / 4; },
       [&](double s) { return (mu + lam / 2) * (s * s - 1) * s; }},
      {&corot, [&](double s) { return (mu + lam / 2) * (s - 1) * (s - 1); },
       [&](double s) { return (2 * mu + lam) * (s - 1); }},
      {&linear, [&](double s) { return (mu + lam / 2) * (s - 1) * (s - 1); },
       [&](double s) { return (2 * mu + lam) * (s - 1); }},
      {&mr, [&](double s) { return (c10 + c01) * (s - 1 / s) * (s - 1 / s); },
       [&](double s) { return 2 * (c10 + c01) * (s - 1 / s) * (1 + 1 / (s * s)); }},
      {&arap, [&](double s) { return muA / 2 * (s - 1) * (s - 1); },
       [&](double s) { return muA * (s - 1); }},
      {&sq, [&](double s) { return muA / 2 * (s - 1) * (s - 1); },
       [&](double s) { return muA * (s - 1); }},
      {&astvk, [&](double s) { return muA / 2 * (s * s - 1) * (s * s - 1); },
       [&](double s) { return 2 * muA * s * (s * s - 1); }},
      // Active fibre: the ARAP row with target gamma (math-spec 7).
      {&active, [&](double s) { return muA / 2 * (s - g) * (s - g); },
       [&](double s) { return muA * (s - g); }},
  };
  for (const Row& r : rows) {
    for (double s : {0.3, 0.5, 0.8, 1.3, 2.0}) {
      const Mat2 F = Vec2(s, 1.0).asDiagonal();
      SCOPED_TRACE(r.m->name() + ", F = diag(" + std::to_string(s) + ", 1)");
      const double expected = r.psi(s);
      EXPECT_NEAR(r.m->psi(F, FIBER_X), expected, 1e-13 * (1.0 + std::abs(expected)));
      const Mat2 P = r.m->pk1(F, FIBER_X);
      EXPECT_NEAR(P(0, 0), r.p11(s), 1e-13 * (1.0 + std::abs(r.p11(s))));
      EXPECT_NEAR(P(0, 1), 0.0, 1e-14);
      EXPECT_NEAR(P(1, 0), 0.0, 1e-14);
    }
  }
}

// ------------------------------------------------------------ ARAP and inversion (math-spec 13, 7)

TEST(AnisotropicArap, InversionCaseOfMathSpec13) {
  const AnisotropicArap arap(PARAMS);
  const double mu = PARAMS.mu_aniso;
  // diag(-0.5, 1): sigma = -1, psi = mu/2 (0.5 + 1)^2 = 1.125 mu.
  EXPECT_NEAR(arap.psi(Mat2(Vec2(-0.5, 1.0).asDiagonal()), FIBER_X), 1.125 * mu, 1e-14);
  // diag(-2, 1): sigma = +1, psi = mu/2 (2 - 1)^2 = 0.5 mu.
  EXPECT_NEAR(arap.psi(Mat2(Vec2(-2.0, 1.0).asDiagonal()), FIBER_X), 0.5 * mu, 1e-14);
}

TEST(AnisotropicArap, AgreesWithSqrtForPositiveDetAndDiffersWhenInverted) {
  // s = +1 makes sigma = +1 and ARAP == Sqrt; only the inversion-aware mode separates them
  // (math-spec 7, 12 item 7). When sigma = -1 the energies differ by exactly 2 mu_A |F a|.
  const AnisotropicArap arap(PARAMS);
  const AnisotropicSqrt sq(PARAMS);
  int same = 0, differ = 0;
  for (const FCase& c : test::material_cases()) {
    SCOPED_TRACE(c.describe());
    const ElementMaterialData d = c.data();
    if (c.F.determinant() > 0.0) {
      EXPECT_EQ(arap.psi(c.F, d), sq.psi(c.F, d));
      EXPECT_EQ(arap.pk1(c.F, d), sq.pk1(c.F, d));
      ++same;
    } else if (fiber_sign(c.F, c.a) < 0.0) {
      const double r = (c.F * c.a).norm();
      EXPECT_NEAR(arap.psi(c.F, d) - sq.psi(c.F, d), 2.0 * PARAMS.mu_aniso * r, 1e-12 * (1 + r));
      EXPECT_GT((arap.pk1(c.F, d) - sq.pk1(c.F, d)).norm(), 1e-3);
      ++differ;
    }
  }
  EXPECT_GE(same, 40);
  EXPECT_GE(differ, 5);
}

TEST(AnisotropicArap, EnergyJumpsAcrossTheSignSurface) {
  // psi is discontinuous at I4 = 0 by 2 mu_A sqrt(I5) (math-spec 7). F = diag(-t, 1) with
  // a = (1, 0): I5 + det F = t^2 - t changes sign at t = 1.
  const AnisotropicArap arap(PARAMS);
  const double below = arap.psi(Mat2(Vec2(-(1.0 - 1e-9), 1.0).asDiagonal()), FIBER_X);
  const double above = arap.psi(Mat2(Vec2(-(1.0 + 1e-9), 1.0).asDiagonal()), FIBER_X);
  EXPECT_NEAR(below - above, 2.0 * PARAMS.mu_aniso, 1e-6);
}

// ------------------------------------------------------------ C-form (math-spec 4.4)

/// A random 2x3 p with orthonormal rows (the current frame), from the case index.
Mat23 frame_rows(int k) {
  const Mat3 Q =
      Eigen::AngleAxisd(0.4 + 0.9 * k, Vec3(1.0, 2.0 + k, -1.0).normalized()).toRotationMatrix();
  return Q.topRows<2>();
}

TEST(CForm, LiftedPk1EqualsFTimesSecondPiolaForCBasedEnergies) {
  // P3 = p^T Pbar must equal F3 S(C) with F3 = p^T Fbar, C = F3^T F3 and S = 2 dpsi/dC written
  // from the C-forms of math-spec 6.1, 6.4 and 7 (a separate derivation from the PK1 code).
  const double mu = PARAMS.mu, lam = PARAMS.lambda, c10 = PARAMS.c10, c01 = PARAMS.c01,
               muA = PARAMS.mu_aniso;
  const Stvk stvk(PARAMS);
  const MooneyRivlin mr(PARAMS);
  const AnisotropicStvk astvk(PARAMS);
  const AnisotropicSqrt sq(PARAMS);
  const AnisotropicArap arap(PARAMS);
  const Mat2 I = Mat2::Identity();
  int k = 0, arap_checked = 0;
  for (const FCase& c : test::material_cases()) {
    // The MR C-form oracle J^-2 C^-1 ~ J^-4 cancels down to the J^-3 of the F-form, losing
    // ~|J|^-4 * 1e-16 in relative accuracy; it is a useful reference only for well-shaped F.
    // (The near-degenerate cases are covered by the FD test, which has no such cancellation.)
    if (std::abs(c.F.determinant()) < 1e-2) continue;
    SCOPED_TRACE(c.describe());
    const Mat23 p = frame_rows(k++);
    const Mat32 F3 = p.transpose() * c.F;
    const Mat2 C = F3.transpose() * F3;
    const Mat2 A = c.a * c.a.transpose();
    const double I5 = c.a.dot(C * c.a);
    const double J2 = C.determinant();  // J^2
    const double IC = C.trace();
    const Mat2 Cinv = C.inverse();
    const Mat2 E = 0.5 * (C - I);
    const Mat2 S_stvk = 2 * mu * E + lam * E.trace() * I;
    const Mat2 S_mr = 2 * c10 * (I - Cinv / J2) + 2 * c01 * (J2 * Cinv + I / J2 - IC / J2 * Cinv);
    const Mat2 S_astvk = 2 * muA * (I5 - 1) * A;
    const Mat2 S_sqrt = muA * (1 - 1 / std::sqrt(I5)) * A;
    const ElementMaterialData d = c.data();
    auto check = [&](const MembraneMaterial& m, const Mat2& S) {
      const Mat32 lifted = p.transpose() * m.pk1(c.F, d);
      const Mat32 expected = F3 * S;
      EXPECT_LE((lifted - expected).norm(), 1e-11 * (1.0 + expected.norm())) << m.name();
    };
    check(stvk, S_stvk);
    check(mr, S_mr);
    check(astvk, S_astvk);
    check(sq, S_sqrt);
    if (fiber_sign(c.F, c.a) > 0.0) {  // ARAP is C-based only where sigma = +1 (math-spec 4.4)
      check(arap, S_sqrt);
      ++arap_checked;
    }
  }
  EXPECT_GE(k, 85);
  EXPECT_GE(arap_checked, 60);
}

// ------------------------------------------------------------ small strain

/// max over a few directions H of |P_model(I + eps H) - P_lin(I + eps H)|_F, and |P_lin|.
template <class M>
std::pair<double, double> small_strain_gap(const M& model, const Linear& lin, double eps) {
  const std::vector<Mat2> Hs{(Mat2() << 0.3, -0.7, 0.5, 0.9).finished(),
                             (Mat2() << -1.0, 0.2, 0.2, 0.4).finished(),
                             (Mat2() << 0.0, 1.0, -0.4, 0.0).finished()};
  double gap = 0.0, scale = std::numeric_limits<double>::infinity();
  for (const Mat2& H : Hs) {
    const Mat2 F = Mat2::Identity() + eps * H;
    gap = std::max(gap, (model.pk1(F, FIBER_X) - lin.pk1(F, FIBER_X)).norm());
    scale = std::min(scale, lin.pk1(F, FIBER_X).norm());
  }
  return {gap, scale};
}

/// Checks |P_model - P_lin| = O(eps^2): the gap shrinks ~100x per decade of eps, while P_lin
/// itself is O(eps) and nonzero.
template <class M>
void expect_second_order_agreement(const M& model, const Linear& lin, const std::string& what) {
  SCOPED_TRACE(what);
  const auto [g2, s2] = small_strain_gap(model, lin, 1e-2);
  const auto [g3, s3] = small_strain_gap(model, lin, 1e-3);
  const auto [g4, s4] = small_strain_gap(model, lin, 1e-4);
  EXPECT_GT(s4, 1e-6) << "linear PK1 must be nonzero";
  EXPECT_LT(g3 / g2, 0.02) << "gaps " << g2 << ", " << g3;
  EXPECT_LT(g4 / g3, 0.02) << "gaps " << g3 << ", " << g4;
  EXPECT_LT(g4 / s4, 1e-3) << "relative gap at eps = 1e-4";
}

TEST(SmallStrain, NonlinearIsotropicModelsLinearizeToLinearElasticity) {
  const Linear lin(PARAMS);
  expect_second_order_agreement(Stvk(PARAMS), lin, "stvk");
  expect_second_order_agreement(Corotated(PARAMS), lin, "corotated");
}

TEST(SmallStrain, MooneyRivlinIsLinearElasticityWithMu2C10C01AndLambdaTwoMu) {
  // Incompressible in plane stress: the 3D incompressibility eps33 = -tr(eps) turns into a
  // finite membrane lambda = 2 mu (not infinity), with mu = 2 (C10 + C01) (math-spec 6.4).
  MaterialParams matched;
  matched.mu = 2.0 * (PARAMS.c10 + PARAMS.c01);
  matched.lambda = 2.0 * matched.mu;
  expect_second_order_agreement(MooneyRivlin(PARAMS), Linear(matched), "mooney-rivlin");
  // Control: with lambda = mu (the wrong membrane lambda) the gap is only first order, so the
  // check above really identifies lambda.
  MaterialParams wrong = matched;
  wrong.lambda = matched.mu;
  const auto [g3, s3] = small_strain_gap(MooneyRivlin(PARAMS), Linear(wrong), 1e-3);
  const auto [g4, s4] = small_strain_gap(MooneyRivlin(PARAMS), Linear(wrong), 1e-4);
  EXPECT_GT(g4 / g3, 0.05) << "gaps " << g3 << ", " << g4;
}

// ------------------------------------------------------------ Mooney-Rivlin at rest and near it

TEST(MooneyRivlinRest, RigidMotionsOfATriangleHaveNoEnergyBeyondRoundingSquared) {
  // A triangle moved rigidly has Fbar = I up to the rounding of its frame (math-spec 4.3). Its
  // energy must be ~eps^2 C10, as StVK's Green strain gives, not the ~eps C10 of the written
  // form's O(1) terms cancelling: PBD skips a constraint only below 1e-16 of the stiffness, and
  // its scale-free step moves a triangle with more energy than that. psi is even in J, so the
  // mirrored triangle (orientation s = -1) is at rest too.
  const MooneyRivlin mr(PARAMS);
  const Stvk stvk(PARAMS);  // the control: C-based, no cancellation
  const ElementMaterialData d;
  EXPECT_EQ(mr.psi(Mat2::Identity(), d), 0.0);
  EXPECT_EQ(mr.pk1(Mat2::Identity(), d), Mat2::Zero());
  std::mt19937 rng(61);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  auto point = [&] { return Vec3(uni(rng), uni(rng), uni(rng)); };
  // psi of Fbar = I + e (e the frame's rounding) is second order in e: at small strain
  // psi = mu |eps|^2 + mu tr(eps)^2 with mu = 2 (C10 + C01), at most 16 (C10 + C01) max|e|^2.
  const double c = PARAMS.c10 + PARAMS.c01;
  auto check = [&](const Vec3& x1, const Vec3& x2, const Vec3& x3, const Mat3& Q, const Vec3& t,
                   double absolute) {
    const TriangleRest rest = triangle_rest(x1, x2, x3);
    ASSERT_FALSE(rest.degenerate);
    for (double s : {1.0, -1.0}) {
      TriangleFrame fr;
      ASSERT_TRUE(
          triangle_frame(Q * x1 + t, Q * x2 + t, Q * x3 + t, rest.Dm_inv, rest.area, s, fr));
      SCOPED_TRACE("Fbar = " + matrix_string(fr.F));
      const double e = (fr.F - Vec2(1.0, s).asDiagonal().toDenseMatrix()).cwiseAbs().maxCoeff();
      const double psi = mr.psi(fr.F, d);
      EXPECT_GE(psi, 0.0);
      EXPECT_LE(psi, 32.0 * c * e * e);
      EXPECT_LE(psi, absolute);
      EXPECT_LE(mr.pk1(fr.F, d).norm(), 1e-13 * PARAMS.c10);
      EXPECT_LE(std::abs(stvk.psi(fr.F, d)), 32.0 * (PARAMS.mu + PARAMS.lambda) * e * e);
    }
  };
  // A unit equilateral triangle turned about the origin: Fbar within a few ulps of I, psi below
  // 1e-29 C10 (the written form gives ~1e-16 C10).
  const Vec3 e1(1.0, 0.0, 0.0), e2(0.5, std::sqrt(0.75), 0.0), o = Vec3::Zero();
  for (int k = 0; k < 50; ++k) {
    const Mat3 Q = Eigen::AngleAxisd(3.0 * uni(rng), point().normalized()).toRotationMatrix();
    check(e1, e2, o, Q, o, 1e-29 * PARAMS.c10);
  }
  // Random triangles, turned and moved: their frames round more (long edges, coordinates ~10).
  for (int k = 0; k < 200; ++k) {
    const Vec3 x1 = point(), x2 = point(), x3 = point();
    if (triangle_rest(x1, x2, x3).area < 0.05) continue;
    const Mat3 Q = Eigen::AngleAxisd(3.0 * uni(rng), point().normalized()).toRotationMatrix();
    check(x1, x2, x3, Q, 10.0 * point(), 1e-27 * PARAMS.c10);
  }
}

TEST(MooneyRivlinRest, EnergyEqualsClosedFormsToRoundingFromTinyToLargeStrains) {
  // Strains whose energy has a closed form with no cancellation in it (F and det F exact): the
  // energy must hold to rounding relative to its own size however small the strain (the written
  // form of math-spec 6.4 loses everything below ~1e-8), and unchanged at large strains.
  const MooneyRivlin mr(PARAMS);
  const ElementMaterialData d;
  const double c = PARAMS.c10 + PARAMS.c01;
  auto expect_rel = [](double got, double expected, const std::string& what) {
    EXPECT_LE(std::abs(got - expected), 1e-14 * expected)
        << what << ": " << got << " vs " << expected;
  };
  // Simple shear [[1, g], [0, 1]] (and its transpose): J = 1, I_C = 2 + g^2, psi = (C10 + C01) g^2.
  for (double g : {1e-9, -3e-7, 1e-4, 0.02, -0.5, 3.0}) {
    Mat2 F = Mat2::Identity();
    F(0, 1) = g;
    expect_rel(mr.psi(F, d), c * g * g, "shear " + std::to_string(g));
    expect_rel(mr.psi(Mat2(F.transpose()), d), c * g * g, "shear^T " + std::to_string(g));
  }
  // Uniaxial diag(1 + h, 1), either axis, either sign of J (math-spec 13):
  // psi = (C10 + C01) (l - 1/l)^2 = (C10 + C01) (h (2 + h) / l)^2 with l = |1 + h|.
  for (double h :
       {std::ldexp(1.0, -30), -std::ldexp(1.0, -30), std::ldexp(1.0, -15), 0.125, -0.5, 1.5}) {
    const double l = 1.0 + h;
    const double expected = c * (h * (2.0 + h) / l) * (h * (2.0 + h) / l);
    for (double sgn : {1.0, -1.0}) {
      expect_rel(mr.psi(Mat2(Vec2(sgn * l, 1.0).asDiagonal()), d), expected,
                 "uniaxial " + std::to_string(h));
      expect_rel(mr.psi(Mat2(Vec2(1.0, sgn * l).asDiagonal()), d), expected,
                 "uniaxial " + std::to_string(h));
    }
  }
  // Equibiaxial l I, with u = l^2 exact for these h:
  //   psi = C10 (2 u + u^-2 - 3) + C01 (u^2 + 2 / u - 3)
  //       = C10 (u - 1)^2 (2 u + 1) / u^2 + C01 (u - 1)^2 (u + 2) / u, u - 1 = h (2 + h).
  for (double h : {std::ldexp(1.0, -26), -std::ldexp(1.0, -20), 0.25, -0.25, 1.0}) {
    const double l = 1.0 + h, u = l * l, m = h * (2.0 + h);
    const double expected =
        PARAMS.c10 * m * m * (2.0 * u + 1.0) / (u * u) + PARAMS.c01 * m * m * (u + 2.0) / u;
    expect_rel(mr.psi(Mat2(l * Mat2::Identity()), d), expected, "equibiaxial " + std::to_string(h));
  }
}

// ------------------------------------------------------------ Mooney-Rivlin clamp (math-spec 11)

TEST(MooneyRivlinClamp, Pk1IsTheExactGradientInsideTheClampOnBothSigns) {
  const MooneyRivlin mr(PARAMS);
  const ElementMaterialData d;
  for (double J : {3e-7, -3e-7, 6e-7, -8e-7}) {
    const Mat2 F = test::rot2(0.3) * Vec2(1.2, J / 1.2).asDiagonal() * test::rot2(-1.1);
    SCOPED_TRACE("F = " + matrix_string(F));
    ASSERT_LT(std::abs(F.determinant()), MOONEY_RIVLIN_MIN_ABS_J);
    const Mat2 P = mr.pk1(F, d);
    ASSERT_TRUE(P.allFinite());
    ASSERT_GT(P.norm(), 1.0);
    // Steps far below |J| so that no stencil point crosses J = 0 or |J| = J0.
    const auto psi = [&](const Mat2& X) { return mr.psi(X, d); };
    const test::FdSweep sweep = test::fd_sweep(psi, F, P, {1e-9, 1e-10, 1e-11});
    EXPECT_LE(sweep.best_error, 1e-6) << sweep.report();
  }
}

TEST(MooneyRivlinClamp, EnergyIsFiniteAtZeroAreaAndTheForceStillRestoresArea) {
  const MooneyRivlin mr(PARAMS);
  const ElementMaterialData d;
  constexpr double J0 = MOONEY_RIVLIN_MIN_ABS_J;
  // J = 0 exactly: psi = C10 (I_C + 3/J0^2 - 3) + C01 (I_C 3/J0^2 - 3) (the continued barrier).
  const Mat2 F0 = Vec2(1.5, 0.0).asDiagonal();
  const double IC = 2.25;
  EXPECT_NEAR(mr.psi(F0, d),
              PARAMS.c10 * (IC + 3 / (J0 * J0) - 3) + PARAMS.c01 * (IC * 3 / (J0 * J0) - 3),
              1e-12 * mr.psi(F0, d));
  EXPECT_TRUE(mr.pk1(F0, d).allFinite());
  // Moving along sign(J) cof F increases |J|; the energy must decrease that way (barrier kept).
  for (double J : {0.0, 2e-7, -2e-7, 5e-6, -5e-6}) {
    const Mat2 F = Vec2(1.5, J / 1.5).asDiagonal();
    Mat2 cof;
    cof << F(1, 1), -F(1, 0), -F(0, 1), F(0, 0);
    const double sgn = J < 0.0 ? -1.0 : 1.0;
    SCOPED_TRACE("F = " + matrix_string(F));
    EXPECT_LT((mr.pk1(F, d).array() * (sgn * cof).array()).sum(), -1.0);
  }
}

TEST(MooneyRivlinClamp, EnergyAndStressAreContinuousAcrossTheClampThreshold) {
  // C1 continuation: psi and P agree on both sides of |J| = J0 (to the change of F itself).
  const MooneyRivlin mr(PARAMS);
  const ElementMaterialData d;
  constexpr double J0 = MOONEY_RIVLIN_MIN_ABS_J;
  for (double sgn : {1.0, -1.0}) {
    const Mat2 Fin = Vec2(1.0, sgn * J0 * (1 - 1e-10)).asDiagonal();
    const Mat2 Fout = Vec2(1.0, sgn * J0 * (1 + 1e-10)).asDiagonal();
    const double psi_in = mr.psi(Fin, d), psi_out = mr.psi(Fout, d);
    const Mat2 P_in = mr.pk1(Fin, d), P_out = mr.pk1(Fout, d);
    SCOPED_TRACE("F = " + matrix_string(Fin));
    EXPECT_LE(std::abs(psi_in - psi_out), 1e-8 * psi_in);
    EXPECT_LE((P_in - P_out).norm(), 1e-8 * P_in.norm());
  }
}

// ------------------------------------------------------------ fibre guard (math-spec 11)

TEST(FiberGuard, ZeroPk1BelowTheThresholdAndBoundedAbove) {
  const AnisotropicArap arap(PARAMS);
  const AnisotropicSqrt sq(PARAMS);
  const ActiveFiber active(PARAMS);
  const AnisotropicStvk astvk(PARAMS);
  const double muA = PARAMS.mu_aniso;
  const Vec2 a(0.6, 0.8), a_perp(-0.8, 0.6);
  for (double r : {0.0, 1e-12, 0.5 * FIBER_MIN_STRETCH}) {
    // F a = r (1, 0), F a_perp = (0.3, 1.1): a fibre crushed to (almost) nothing.
    const Mat2 F = Vec2(r, 0.0) * a.transpose() + Vec2(0.3, 1.1) * a_perp.transpose();
    const ElementMaterialData d{a};
    SCOPED_TRACE("F = " + matrix_string(F));
    const double sigma = fiber_sign(F, a);
    for (const MembraneMaterial* m :
         {static_cast<const MembraneMaterial*>(&arap), static_cast<const MembraneMaterial*>(&sq),
          static_cast<const MembraneMaterial*>(&active)}) {
      EXPECT_EQ(m->pk1(F, d), Mat2::Zero()) << m->name();
    }
    EXPECT_NEAR(arap.psi(F, d), 0.5 * muA * (r - sigma) * (r - sigma), 1e-15);
    EXPECT_NEAR(sq.psi(F, d), 0.5 * muA * (r - 1) * (r - 1), 1e-15);
    // Anisotropic StVK needs no guard: its PK1 vanishes smoothly, |P| = 2 mu |I5 - 1| r.
    EXPECT_NEAR(astvk.pk1(F, d).norm(), 2 * muA * (1 - r * r) * r, 1e-15);
    EXPECT_NEAR(astvk.psi(F, d), 0.5 * muA * (r * r - 1) * (r * r - 1), 1e-15);
  }
  // The C-form hook has the same guard, and survives a slightly negative a^T C a (round-off).
  for (double i5 : {0.0, -1e-18, 1e-20}) {
    const Mat2 C = Vec2(i5, 1.3).asDiagonal();
    Mat2 S;
    const double psi = sq.psi_second_pk(C, FIBER_X, S);
    EXPECT_EQ(S, Mat2::Zero()) << "a^T C a = " << i5;
    EXPECT_NEAR(psi, 0.5 * muA, 1e-9) << "a^T C a = " << i5;
  }
  // Just above the threshold the ARAP/Sqrt PK1 is bounded by mu_A (1 + 1/|Fa|) |Fa| ~ mu_A.
  const Mat2 F =
      Vec2(2 * FIBER_MIN_STRETCH, 0.0) * a.transpose() + Vec2(0.3, 1.1) * a_perp.transpose();
  const ElementMaterialData d{a};
  EXPECT_NEAR(sq.pk1(F, d).norm(), muA * (1 - 2 * FIBER_MIN_STRETCH), 1e-12);
  EXPECT_TRUE(arap.pk1(F, d).allFinite());
  EXPECT_LE(arap.pk1(F, d).norm(), muA * (1 + 2 * FIBER_MIN_STRETCH) + 1e-12);
}

// ------------------------------------------------------------ polar guard in the corotated model

TEST(CorotatedGuard, FiniteAndContinuousEnergyWhereThePolarRotationIsUndefined) {
  // rho = 0 on F = [[u, v], [v, -u]]; psi = mu (|F|^2 - 2 rho + 2) + lambda/2 (rho - 2)^2 does
  // not need R, so it checks the guarded value (math-spec 6.2: tr(R^T F) = rho).
  const Corotated corot(PARAMS);
  const ElementMaterialData d;
  Mat2 F;
  F << 0.4, -0.9, -0.9, -0.4;
  const double expected = PARAMS.mu * (F.squaredNorm() + 2.0) + 0.5 * PARAMS.lambda * 4.0;
  EXPECT_NEAR(corot.psi(F, d), expected, 1e-14 * expected) << "F = " << matrix_string(F);
  EXPECT_TRUE(corot.pk1(F, d).allFinite());
  Mat2 Fnear = F;
  Fnear(0, 0) += 1e-9;  // rho = 1e-9: the formula branch, same energy to O(1e-9)
  EXPECT_NEAR(corot.psi(Fnear, d), expected, 1e-8);
  EXPECT_TRUE(corot.pk1(Mat2::Zero(), d).allFinite());
  EXPECT_NEAR(corot.psi(Mat2::Zero(), d), 2 * PARAMS.mu + 2 * PARAMS.lambda, 1e-15);
}

// ------------------------------------------------------------ active fibre (math-spec 7)

TEST(ActiveFiber, IdentityIsNotRestWhenGammaBelowOneAndGammaOneIsArap) {
  const ActiveFiber active(PARAMS);
  const double g = PARAMS.fiber_target, muA = PARAMS.mu_aniso;
  const ElementMaterialData d{Vec2(0.6, 0.8)};
  // At F = I the fibre is too long: psi = mu/2 (1 - gamma)^2, P = mu (1 - gamma) a a^T (pulls).
  EXPECT_NEAR(active.psi(Mat2::Identity(), d), 0.5 * muA * (1 - g) * (1 - g), 1e-15);
  EXPECT_LE(
      (active.pk1(Mat2::Identity(), d) - muA * (1 - g) * d.fiber * d.fiber.transpose()).norm(),
      1e-15);
  MaterialParams one = PARAMS;
  one.fiber_target = 1.0;
  const ActiveFiber unit_target(one);
  const AnisotropicArap arap(one);
  for (const FCase& c : test::material_cases()) {
    SCOPED_TRACE(c.describe());
    EXPECT_EQ(unit_target.psi(c.F, c.data()), arap.psi(c.F, c.data()));
    EXPECT_EQ(unit_target.pk1(c.F, c.data()), arap.pk1(c.F, c.data()));
  }
}

TEST(ActiveFiber, RejectsTargetsOutsideZeroOne) {
  for (double g : {0.0, -0.5, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    MaterialParams p = PARAMS;
    p.fiber_target = g;
    EXPECT_THROW(ActiveFiber{p}, UsageError) << "gamma = " << g;
  }
  MaterialParams p = PARAMS;
  p.fiber_target = 1e-3;
  EXPECT_NO_THROW(ActiveFiber{p});
}

}  // namespace
}  // namespace shellcontract
