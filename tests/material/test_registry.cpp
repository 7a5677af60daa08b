// Material registry (names, factories, dispatch templates) and the plane-stress Lame conversion.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <typeinfo>

#include "material/registry.hpp"
#include "material_cases.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract {
namespace {

const MaterialParams PARAMS = test::test_params();

TEST(Registry, MaterialNamesRoundTripAndMatchModelNames) {
  const std::vector<std::string> names = material_names();
  ASSERT_EQ(names, (std::vector<std::string>{"stvk", "corotated", "linear", "mooney-rivlin"}));
  for (const std::string& n : names) {
    SCOPED_TRACE(n);
    const MaterialKind k = parse_material_kind(n);
    EXPECT_EQ(to_string(k), n);
    const auto m = make_material(k, PARAMS);
    ASSERT_NE(m, nullptr);
    EXPECT_EQ(m->name(), n);
  }
}

TEST(Registry, AnisoNamesRoundTripAndMatchModelNames) {
  const std::vector<std::string> names = aniso_names();
  ASSERT_EQ(names, (std::vector<std::string>{"none", "arap", "stvk", "sqrt", "active-fiber"}));
  for (const std::string& n : names) {
    SCOPED_TRACE(n);
    const AnisoKind k = parse_aniso_kind(n);
    EXPECT_EQ(to_string(k), n);
    const auto m = make_aniso(k, PARAMS);
    if (k == AnisoKind::None) {
      EXPECT_EQ(m, nullptr);
    } else {
      ASSERT_NE(m, nullptr);
      EXPECT_EQ(m->name(), n);
    }
    // with_aniso dispatches every kind, None included (NoAniso).
    EXPECT_EQ(with_aniso(k, PARAMS, [](const auto& model) { return model.name(); }), n);
  }
}

TEST(Registry, UnknownNamesThrowAndListTheValidOnes) {
  for (const std::string bad : {"", "StVK", "mooney_rivlin", "no-such-material"}) {
    try {
      parse_material_kind(bad);
      ADD_FAILURE() << "no throw for '" << bad << "'";
    } catch (const UsageError& e) {
      const std::string msg = e.what();
      for (const std::string& n : material_names())
        EXPECT_NE(msg.find(n), std::string::npos) << msg;
    }
  }
  try {
    parse_aniso_kind("ARAP");
    ADD_FAILURE() << "no throw for 'ARAP'";
  } catch (const UsageError& e) {
    const std::string msg = e.what();
    for (const std::string& n : aniso_names()) EXPECT_NE(msg.find(n), std::string::npos) << msg;
  }
  EXPECT_THROW(to_string(static_cast<MaterialKind>(99)), UsageError);
  EXPECT_THROW(make_material(static_cast<MaterialKind>(99), PARAMS), UsageError);
  EXPECT_THROW(make_aniso(static_cast<AnisoKind>(-1), PARAMS), UsageError);
}

TEST(Registry, WithMaterialPassesTheConcreteTypeAndTheParameters) {
  const auto expect_type = [](MaterialKind k, const std::type_info& t) {
    EXPECT_EQ(
        with_material(k, PARAMS, [](const auto& m) -> const std::type_info& { return typeid(m); }),
        t)
        << to_string(k);
  };
  expect_type(MaterialKind::Stvk, typeid(Stvk));
  expect_type(MaterialKind::Corotated, typeid(Corotated));
  expect_type(MaterialKind::Linear, typeid(Linear));
  expect_type(MaterialKind::MooneyRivlin, typeid(MooneyRivlin));
  // The concrete type is static (what the templated solver needs): `final` models only.
  with_material(MaterialKind::Stvk, PARAMS, [](const auto& m) {
    static_assert(std::is_final_v<std::decay_t<decltype(m)>>);
    static_assert(std::is_base_of_v<MembraneMaterial, std::decay_t<decltype(m)>>);
  });  // void-returning functor compiles and runs
  // Parameters reach the model: same numbers as a directly built one on a stressed F.
  const test::FCase c = test::material_cases().front();
  for (const std::string& n : material_names()) {
    const MaterialKind k = parse_material_kind(n);
    const double via =
        with_material(k, PARAMS, [&](const auto& m) { return m.psi(c.F, c.data()); });
    EXPECT_EQ(via, make_material(k, PARAMS)->psi(c.F, c.data())) << n;
    EXPECT_GT(via, 0.0) << n;
  }
  const auto aniso_type = [](AnisoKind k) {
    return std::string(with_aniso(k, PARAMS, [](const auto& m) { return typeid(m).name(); }));
  };
  EXPECT_EQ(aniso_type(AnisoKind::None), typeid(NoAniso).name());
  EXPECT_EQ(aniso_type(AnisoKind::ActiveFiber), typeid(ActiveFiber).name());
  EXPECT_THROW(with_material(static_cast<MaterialKind>(7), PARAMS, [](const auto&) { return 0; }),
               UsageError);
}

TEST(Registry, NoAnisoIsIdenticallyZero) {
  const NoAniso none;
  for (const test::FCase& c : test::material_cases()) {
    EXPECT_EQ(none.psi(c.F, c.data()), 0.0);
    EXPECT_EQ(none.pk1(c.F, c.data()), Mat2::Zero());
  }
  EXPECT_FALSE(none.frame_dependent());
}

TEST(Registry, ActiveFiberParametersAreValidatedThroughTheFactory) {
  MaterialParams p = PARAMS;
  p.fiber_target = 2.0;
  EXPECT_THROW(make_aniso(AnisoKind::ActiveFiber, p), UsageError);
  EXPECT_NO_THROW(make_aniso(AnisoKind::Arap, p));  // gamma is read by the active fibre only
}

// ------------------------------------------------------------ plane-stress Lame (math-spec 6)

TEST(MembraneLame, PlaneStressModuliReproduceTheThreeDimensionalSheet) {
  for (double nu : {-0.5, 0.0, 0.25, 0.3, 0.45, 0.5}) {
    const double E = 2.1e9, h = 1e-3;
    SCOPED_TRACE("E = 2.1e9, h = 1e-3, nu = " + std::to_string(nu));
    const MaterialParams p = membrane_lame_from_young(E, nu, h);
    // Independent route: the in-plane 2D Young's modulus and Poisson ratio of (mu, lambda*)
    // must be E h and nu (uniaxial stress in the plane, sigma_33 = 0 already built in).
    const double E2 = 4.0 * p.mu * (p.mu + p.lambda) / (2.0 * p.mu + p.lambda);
    const double nu2 = p.lambda / (2.0 * p.mu + p.lambda);
    EXPECT_NEAR(E2, E * h, 1e-12 * E * h);
    EXPECT_NEAR(nu2, nu, 1e-14);
    EXPECT_NEAR(p.mu, E * h / (2.0 * (1.0 + nu)), 1e-12 * E * h);  // shear modulus unchanged
    if (nu < 0.5) {
      // lambda* = 2 mu lambda3 / (lambda3 + 2 mu) with the 3D lambda3 (times h).
      const double lambda3 = E * h * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
      EXPECT_NEAR(p.lambda, 2.0 * p.mu * lambda3 / (lambda3 + 2.0 * p.mu), 1e-12 * E * h);
    } else {
      EXPECT_NEAR(p.lambda, 2.0 * p.mu, 1e-12 * E * h);  // incompressible: Mooney-Rivlin's lambda
    }
  }
}

TEST(MembraneLame, InvalidInputThrows) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(membrane_lame_from_young(0.0, 0.3, 1.0), UsageError);
  EXPECT_THROW(membrane_lame_from_young(-1.0, 0.3, 1.0), UsageError);
  EXPECT_THROW(membrane_lame_from_young(1.0, 0.3, 0.0), UsageError);
  EXPECT_THROW(membrane_lame_from_young(1.0, 0.3, -1.0), UsageError);
  EXPECT_THROW(membrane_lame_from_young(1.0, 1.0, 1.0), UsageError);
  EXPECT_THROW(membrane_lame_from_young(1.0, -1.0, 1.0), UsageError);
  EXPECT_THROW(membrane_lame_from_young(nan, 0.3, 1.0), UsageError);
  EXPECT_THROW(membrane_lame_from_young(1.0, nan, 1.0), UsageError);
  EXPECT_THROW(membrane_lame_from_young(1.0, 0.3, inf), UsageError);
  EXPECT_NO_THROW(membrane_lame_from_young(1.0, 0.999, 1.0));
}

}  // namespace
}  // namespace shellcontract
