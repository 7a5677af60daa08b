// Tests over every registered membrane material and anisotropic energy (house-style.md 5, HOBAK's loop
// over all materials): the suite walks the registry (material_names(), aniso_names()) and checks
// each model's concrete type, so a newly registered model is checked without editing this file:
// PK1 against central differences of psi with an eps sweep, zero energy and stress at the model's
// rest state, rotation invariance (and its failure for Linear), PK1 equivariance, and
// frame_dependent() against the model's actual sensitivity to the orientation s. A model whose
// contract differs from Expect's defaults (frame-dependent, not rotation-invariant, another rest
// state) states it in an Expect specialization below.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <ostream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "material/active_fiber.hpp"
#include "material/anisotropic_arap.hpp"
#include "material/anisotropic_sqrt.hpp"
#include "material/anisotropic_stvk.hpp"
#include "material/corotated.hpp"
#include "material/linear.hpp"
#include "material/mooney_rivlin.hpp"
#include "material/registry.hpp"
#include "material/stvk.hpp"
#include "material_cases.hpp"
#include "support/fd_check.hpp"

namespace shellcontract {
namespace {

using test::FCase;
using test::material_cases;
using test::rot2;

/// Relative PK1-vs-FD tolerance (math-spec 13: item 3's check with item 2's relative bound).
constexpr double FD_TOL = 1e-6;

/// What each model is expected to be; written from the math-spec, not from the code.
template <class M>
struct Expect {
  static constexpr bool rotation_invariant = true;  // math-spec 4.4
  static constexpr bool frame_dependent = false;    // depends on C = F^T F only
  /// The model's rest state for fibre a (F = I unless stated).
  static Mat2 rest(const Vec2&) { return Mat2::Identity(); }
};
template <>
struct Expect<Linear> {
  static constexpr bool rotation_invariant = false;  // math-spec 6.3
  static constexpr bool frame_dependent = true;
  static Mat2 rest(const Vec2&) { return Mat2::Identity(); }
};
template <>
struct Expect<Corotated> {
  static constexpr bool rotation_invariant = true;
  static constexpr bool frame_dependent = true;  // rho^2 = tr C + 2 det F
  static Mat2 rest(const Vec2&) { return Mat2::Identity(); }
};
template <>
struct Expect<AnisotropicArap> {
  static constexpr bool rotation_invariant = true;
  static constexpr bool frame_dependent = true;  // sigma = sign(I5 + det F)
  static Mat2 rest(const Vec2&) { return Mat2::Identity(); }
};
template <>
struct Expect<ActiveFiber> {
  static constexpr bool rotation_invariant = true;
  static constexpr bool frame_dependent = true;  // sigma = sign(I5 + det F)
  /// Rest at the target stretch: F a = gamma a, F a_perp = a_perp (math-spec 7).
  static Mat2 rest(const Vec2& a) {
    return Mat2::Identity() + (test::test_params().fiber_target - 1.0) * a * a.transpose();
  }
};

/// True when M offers the frame-free C-form psi_second_pk(C, data, S) that the PBD kernel
/// prefers (pbd/constraint_kernels.hpp has_second_pk; redeclared here so the material tests do
/// not depend on pbd/).
template <class M, class = void>
struct HasCForm : std::false_type {};
template <class M>
struct HasCForm<M, std::void_t<decltype(std::declval<const M&>().psi_second_pk(
                       std::declval<const Mat2&>(), std::declval<const ElementMaterialData&>(),
                       std::declval<Mat2&>()))>> : std::true_type {};

/// Models expected to offer the C-form: the C-only energies except Mooney-Rivlin, whose clamped
/// S diverges at det C = 0 (see mooney_rivlin.hpp).
template <class M>
constexpr bool EXPECT_C_FORM = std::is_same_v<M, Stvk> || std::is_same_v<M, AnisotropicStvk> ||
                               std::is_same_v<M, AnisotropicSqrt>;

/// One registered model: a membrane material (material_names()) or an anisotropic energy
/// (aniso_names(), without "none", which has no energy to check).
struct Registered {
  bool aniso = false;
  std::string name;
};

void PrintTo(const Registered& r, std::ostream* os) { *os << (r.aniso ? "aniso " : "") << r.name; }

std::vector<Registered> registered_models() {
  std::vector<Registered> out;
  for (const std::string& n : material_names()) out.push_back({false, n});
  for (const std::string& n : aniso_names())
    if (parse_aniso_kind(n) != AnisoKind::None) out.push_back({true, n});
  return out;
}

std::string test_name(const ::testing::TestParamInfo<Registered>& info) {
  std::string out = (info.param.aniso ? "aniso_" : "") + info.param.name;
  for (char& ch : out)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return out;
}

class MaterialTest : public ::testing::TestWithParam<Registered> {
 protected:
  /// Calls check(const M& model) with the registered model's concrete type M.
  template <class Check>
  void with_model(Check&& check) const {
    const Registered& r = GetParam();
    if (r.aniso)
      with_aniso(parse_aniso_kind(r.name), test::test_params(), check);
    else
      with_material(parse_material_kind(r.name), test::test_params(), check);
  }
  const std::vector<FCase> cases = material_cases();
};

INSTANTIATE_TEST_SUITE_P(Registry, MaterialTest, ::testing::ValuesIn(registered_models()),
                         test_name);

TEST_P(MaterialTest, Pk1MatchesCentralDifferencesOfPsi) {
  with_model([&](const auto& model) {
    std::map<std::string, int> compared, total;
    for (const FCase& c : this->cases) {
      ++total[c.label];
      if (!test::fd_smooth(c)) continue;
      SCOPED_TRACE(c.describe());
      const ElementMaterialData d = c.data();
      const Mat2 P = model.pk1(c.F, d);
      // Zero must not match zero: every kept case is a stressed state for every model.
      ASSERT_GT(P.norm(), 1e-6) << "analytic PK1 is (near) zero";
      const auto psi = [&](const Mat2& X) { return model.psi(X, d); };
      const test::FdSweep sweep = test::fd_sweep(psi, c.F, P);
      EXPECT_LE(sweep.best_error, FD_TOL) << sweep.report();
      ++compared[c.label];
    }
    int n_compared = 0;
    for (const auto& entry : compared) n_compared += entry.second;
    this->RecordProperty("fd_cases_compared", n_compared);
    std::printf("[ info     ] %d of %zu cases compared\n", n_compared, this->cases.size());
    // The smoothness filter must leave every category in play (else the test proves little).
    for (const auto& [label, n] : total) {
      EXPECT_GE(compared[label], (n + 1) / 2) << "category " << label << " mostly filtered out";
    }
  });
}

TEST_P(MaterialTest, ZeroEnergyAndStressAtRest) {
  with_model([&](const auto& model) {
    using Model = std::decay_t<decltype(model)>;
    const double mu = test::test_params().mu;
    for (double t : {0.0, 0.3, 1.0, 2.0}) {
      ElementMaterialData d;
      d.fiber = Vec2(std::cos(t), std::sin(t));
      const Mat2 F = Expect<Model>::rest(d.fiber);
      SCOPED_TRACE("rest F = " + test::matrix_string(F) + ", a = " + test::matrix_string(d.fiber));
      EXPECT_LE(std::abs(model.psi(F, d)), 1e-12 * mu);
      EXPECT_LE(model.pk1(F, d).norm(), 1e-12 * mu);
    }
  });
}

TEST_P(MaterialTest, RotationInvarianceMatchesContract) {
  with_model([&](const auto& model) {
    using Model = std::decay_t<decltype(model)>;
    // psi(Q F) = psi(F) and P(Q F) = Q P(F) for Q in SO(2) (math-spec 4.4); Linear must FAIL it.
    double worst_psi = 0.0, worst_pk1 = 0.0;
    int k = 0;
    for (const FCase& c : this->cases) {
      const Mat2 Q = rot2(0.7 + 0.37 * (k++));
      const ElementMaterialData d = c.data();
      const double psi0 = model.psi(c.F, d);
      const double psi1 = model.psi(Q * c.F, d);
      const Mat2 P0 = model.pk1(c.F, d);
      const Mat2 P1 = model.pk1(Q * c.F, d);
      const double e_psi = std::abs(psi1 - psi0) / std::max(1.0, std::abs(psi0));
      const double e_pk1 = (P1 - Q * P0).norm() / std::max(1.0, P0.norm());
      worst_psi = std::max(worst_psi, e_psi);
      worst_pk1 = std::max(worst_pk1, e_pk1);
      if (Expect<Model>::rotation_invariant) {
        SCOPED_TRACE(c.describe() + ", Q = " + test::matrix_string(Q));
        EXPECT_LE(e_psi, 1e-12);
        EXPECT_LE(e_pk1, 1e-12);
      }
    }
    if (!Expect<Model>::rotation_invariant) {
      EXPECT_GT(worst_psi, 1e-3) << "Linear is documented as not rotation-invariant";
      EXPECT_GT(worst_pk1, 1e-3);
    }
  });
}

TEST_P(MaterialTest, FrameDependentFlagMatchesReflectionSensitivity) {
  with_model([&](const auto& model) {
    using Model = std::decay_t<decltype(model)>;
    // M F with M = diag(1, -1) has the same C = F^T F but the opposite det: the orientation s
    // flipped (math-spec 4.2). C-only models must not notice; frame-dependent ones must, on some
    // case. This pins the documented meaning of frame_dependent().
    EXPECT_EQ(model.frame_dependent(), Expect<Model>::frame_dependent);
    const Mat2 M = Vec2(1.0, -1.0).asDiagonal();
    double worst = 0.0;
    for (const FCase& c : this->cases) {
      const ElementMaterialData d = c.data();
      const double psi0 = model.psi(c.F, d);
      const double e = std::abs(model.psi(M * c.F, d) - psi0) / std::max(1.0, std::abs(psi0));
      worst = std::max(worst, e);
      if (!Expect<Model>::frame_dependent) {
        SCOPED_TRACE(c.describe());
        EXPECT_LE(e, 1e-12);
      }
    }
    if (Expect<Model>::frame_dependent) {
      EXPECT_GT(worst, 1e-3) << "documented as frame-dependent but blind to the orientation s";
    }
  });
}

TEST_P(MaterialTest, CFormHookAgreesWithTheFForm) {
  with_model([&](const auto& model) {
    using Model = std::decay_t<decltype(model)>;
    // psi_second_pk(F^T F) must give psi(F) and P = F S (math-spec 4.4), on every case including
    // inverted and near-degenerate ones (the C-path is what the kernel runs on collapsed
    // triangles).
    EXPECT_EQ(HasCForm<Model>::value, EXPECT_C_FORM<Model>);
    if constexpr (HasCForm<Model>::value) {
      ASSERT_FALSE(model.frame_dependent()) << "a C-form model cannot be frame-dependent";
      for (const FCase& c : this->cases) {
        SCOPED_TRACE(c.describe());
        const ElementMaterialData d = c.data();
        Mat2 S = Mat2::Constant(std::nan(""));
        const double psi_c = model.psi_second_pk(c.F.transpose() * c.F, d, S);
        const double psi_f = model.psi(c.F, d);
        const Mat2 P = model.pk1(c.F, d);
        EXPECT_NEAR(psi_c, psi_f, 1e-13 * (1.0 + std::abs(psi_f)));
        EXPECT_LE((S - S.transpose()).norm(), 1e-14 * (1.0 + S.norm()));
        EXPECT_LE((c.F * S - P).norm(), 1e-13 * (1.0 + P.norm()));
      }
    }
  });
}

TEST_P(MaterialTest, VirtualAndConcreteCallsAgree) {
  with_model([&](const auto& model) {
    // The solver calls the concrete type, tools call through the interface: same numbers.
    const MembraneMaterial& base = model;
    for (const FCase& c : this->cases) {
      SCOPED_TRACE(c.describe());
      const ElementMaterialData d = c.data();
      EXPECT_EQ(base.psi(c.F, d), model.psi(c.F, d));
      EXPECT_EQ(base.pk1(c.F, d), model.pk1(c.F, d));
      EXPECT_TRUE(std::isfinite(base.psi(c.F, d)));
      EXPECT_TRUE(base.pk1(c.F, d).allFinite());
    }
  });
}

}  // namespace
}  // namespace shellcontract
