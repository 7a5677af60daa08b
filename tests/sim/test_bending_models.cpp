// Every bending model --bending accepts (sim/bending_models.hpp, the list its parser and --help
// are made from) runs a short contraction of a small mesh to a finite, smaller result, and each
// is at rest where its energy says: the dihedral one at the input, the isometric one flat (so
// not at a closed input), none nowhere.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include "shellcontract/mesh_io.hpp"
#include "shellcontract/observer.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"
#include "sim/bending_models.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

/// The bending energy after each step.
class BendingEnergies final : public RunObserver {
 public:
  void frame(const FrameView& /*view*/, const FrameMetrics& m) override {
    energies.push_back(m.energies.bending);
  }
  std::vector<double> energies;
};

struct BendingRun {
  RunResult result;
  std::vector<double> energies;
};

BendingRun run(const std::string& model, const char* pressure) {
  static const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/ico2.off");
  RunOptions o;
  set_run_option(o, "bending", model);
  set_run_option(o, "pressure", pressure);
  set_run_option(o, "frames", "30");
  BendingEnergies energies;
  BendingRun r{run_contraction(mesh, o, &energies), {}};
  r.energies = energies.energies;
  return r;
}

TEST(BendingModels, EveryModelContractsASmallMeshToAFiniteResult) {
  const OptionSpec* bending = find_run_option("bending");
  ASSERT_NE(bending, nullptr);
  ASSERT_GE(bending_models().size(), 3u);
  for (const auto& model : bending_models()) {
    RunOptions o;
    ASSERT_NO_THROW(bending->set(o, model.name)) << model.name;
    EXPECT_EQ(o.sim.bending, model.value) << model.name;
    EXPECT_EQ(bending->get(o), model.name);
    const BendingRun r = run(model.name, "2");
    EXPECT_EQ(r.result.status, RunStatus::Completed) << model.name << ": " << r.result.message;
    EXPECT_TRUE(r.result.positions.allFinite()) << model.name;
    EXPECT_TRUE(std::isfinite(r.result.final_volume_ratio)) << model.name;
    EXPECT_LT(r.result.final_volume_ratio, 1.0) << model.name;
    ASSERT_EQ(r.energies.size(), 30u) << model.name;
    for (double e : r.energies)
      EXPECT_TRUE(std::isfinite(e) && e >= 0.0) << model.name << ": " << e;
  }
}

TEST(BendingModels, EachModelIsAtRestWhereItsEnergyIs) {
  for (const auto& model : bending_models()) {
    // No pressure and nothing else to drive the shell: only the bending energy can move it.
    const BendingRun r = run(model.name, "0");
    ASSERT_FALSE(r.energies.empty()) << model.name;
    switch (model.value) {
      case BendingModel::Dihedral:  // at rest at the input: no energy, no motion
        EXPECT_LT(r.energies.front(), 1e-12) << model.name;
        EXPECT_NEAR(r.result.final_volume_ratio, 1.0, 1e-9) << model.name;
        break;
      case BendingModel::Isometric:  // at rest flat: a closed shell is not, and it moves
        EXPECT_GT(r.energies.front(), 0.0) << model.name;
        EXPECT_LT(r.result.final_volume_ratio, 1.0) << model.name;
        break;
      case BendingModel::None:  // no energy at all, and the membrane alone is at rest
        for (double e : r.energies) EXPECT_EQ(e, 0.0) << model.name;
        EXPECT_NEAR(r.result.final_volume_ratio, 1.0, 1e-9) << model.name;
        break;
    }
  }
}

TEST(BendingModels, HelpNamesEachModelOnce) {
  // The help listed them twice ("isometric (...) | dihedral (...) | none; isometric | dihedral |
  // none"): it is made from the list now, each name once with what it is.
  const std::string& help = find_run_option("bending")->help;
  for (const auto& model : bending_models()) {
    const std::regex word("(^|[^a-z-])" + model.name + "($|[^a-z-])");
    const auto n =
        std::distance(std::sregex_iterator(help.begin(), help.end(), word), std::sregex_iterator());
    EXPECT_EQ(n, 1) << model.name << " in: " << help;
    if (!model.description.empty()) {
      EXPECT_NE(help.find(model.name + " (" + model.description + ")"), std::string::npos) << help;
    }
  }
}

}  // namespace
}  // namespace shellcontract
