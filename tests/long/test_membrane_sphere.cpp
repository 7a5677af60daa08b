// Issue "Control", item 4: dV/V of a pressurized spherical membrane in XPBD against the closed
// form (docs/math/membrane-sphere.md) on icospheres of 1280, 5120 and 20480 faces, at three
// pressures well below buckling, within 5 %. Label "long"; prints the table of the README.
#include "support/membrane_sphere_case.hpp"

namespace shellcontract {
namespace {

class MembraneSphere : public ::testing::TestWithParam<int> {};

TEST_P(MembraneSphere, VolumeChangeMatchesTheClosedForm) {
  const test::MembraneSphereSetting s;
  const double buckling = test::membrane_sphere_buckling(s);
  for (double fraction : {0.01, 0.02, 0.04}) {
    const double P = fraction * buckling;
    const double want = test::membrane_sphere_dv(P, s);
    const double got = test::membrane_sphere_measured(GetParam(), P, s);
    std::cout << "membrane sphere: faces " << 20 * (1 << (2 * GetParam())) << ", P " << P << " (" << fraction
              << " P_c): dV/V " << got << ", closed form " << want << ", ratio " << got / want << '\n';
    EXPECT_NEAR(got / want, 1.0, 0.05) << "P = " << P;
  }
}

INSTANTIATE_TEST_SUITE_P(Icospheres, MembraneSphere, ::testing::Values(3, 4, 5));

}  // namespace
}  // namespace shellcontract
