// The projections' skip floor (math-spec 9.1(d): a membrane projection with E <= 1e-16 k Abar is
// skipped) takes its scale k from the energies in use only. It had been the largest of every
// stiffness parameter, those of materials not chosen included (C10's default 0.5 and mu_A's 1):
// under PBD, whose step is otherwise free of the stiffness's scale, a membrane of mu = 1e-12 was
// skipped up to strains of 1e-2, and --c10 or --mu-a, which the run warns have no effect, changed
// the result (review numguards M2).
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

RunOptions options_from(const std::vector<std::pair<std::string, std::string>>& given) {
  RunOptions o;
  for (const auto& [name, value] : given) set_run_option(o, name, value);
  return o;
}

Positions result(const std::vector<std::pair<std::string, std::string>>& given) {
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/ico2.off");
  std::vector<std::pair<std::string, std::string>> all{{"frames", "20"}, {"collisions", "off"}};
  all.insert(all.end(), given.begin(), given.end());
  const RunResult r = run_contraction(mesh, options_from(all));
  EXPECT_EQ(r.status, RunStatus::Completed) << r.message;
  return r.positions;
}

double largest_distance(const Positions& a, const Positions& b) {
  return (a - b).rowwise().norm().maxCoeff();
}

TEST(EnergyFloor, APbdRunIsFreeOfTheMembranesScale) {
  // PBD's step depends on mu and lambda by their ratio only: 1e-12 of each moves as 1 of each, to
  // rounding (a bound far below the run's motion; a skipped membrane moves them by more than it).
  const Positions unit = result({{"solver", "pbd"}, {"mu", "1"}, {"lambda", "1"}});
  const Positions soft = result({{"solver", "pbd"}, {"mu", "1e-12"}, {"lambda", "1e-12"}});
  EXPECT_LT(largest_distance(unit, soft), 1e-12);
}

TEST(EnergyFloor, ParametersOfEnergiesNotInUseChangeNoBit) {
  for (const std::string solver : {"pbd", "xpbd"}) {
    SCOPED_TRACE(solver);
    const Positions plain = result({{"solver", solver}, {"mu", "1e-12"}, {"lambda", "1e-12"}});
    // Mooney-Rivlin's C10 and the fibre stiffness without --aniso: each warned as of no effect.
    EXPECT_EQ(plain,
              result({{"solver", solver}, {"mu", "1e-12"}, {"lambda", "1e-12"}, {"c10", "1e-13"}}));
    EXPECT_EQ(plain,
              result({{"solver", solver}, {"mu", "1e-12"}, {"lambda", "1e-12"}, {"mu-a", "1e14"}}));
    EXPECT_EQ(plain,
              result({{"solver", solver}, {"mu", "1e-12"}, {"lambda", "1e-12"}, {"mu-a", "0"}}));
  }
  // Under the defaults (StVK from --young and --thickness) as well.
  EXPECT_EQ(result({}), result({{"mu-a", "1e14"}}));
}

}  // namespace
}  // namespace shellcontract
