// The run's summary (write_run_summary) as a reader takes it: a resumed run's mean_step_ms is its
// own time over its own frames, target_reached has no value when nothing was to be reached, and
// the masses raised for the pressure are counted (and many are a warning).
#include <gtest/gtest.h>

#include <map>
#include <optional>
#include <string>

#include "core/usable_cpus.hpp"
#include "shellcontract/checkpoint.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/report.hpp"
#include "shellcontract/run.hpp"
#include "sim/mass_scaling.hpp"
#include "sim/simulator.hpp"
#include "support/cgal_mesh.hpp"
#include "support/memory_checkpointer.hpp"
#include "support/mesh_fixtures.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

/// The top-level keys a summary writes: numbers, booleans, and the keys written as null.
class Recorder final : public SummaryWriter {
 public:
  void add_bool(const std::string& k, bool v) override { bools[k] = v; }
  void add_null(const std::string& k) override { nulls[k] = true; }
  void add_integer(const std::string& k, long long v) override {
    numbers[k] = static_cast<double>(v);
  }
  void add_number(const std::string& k, double v) override { numbers[k] = v; }
  void add_text(const std::string&, const std::string&) override {}
  void add_texts(const std::string&, const std::vector<std::string>&) override {}
  void add_object(const std::string&, const std::function<void(SummaryWriter&)>&) override {}
  std::map<std::string, double> numbers;
  std::map<std::string, bool> bools, nulls;
};

Recorder summary_of(const RunOptions& o, const RunResult& r) {
  Recorder w;
  write_run_summary(w, InputReport{}, o, r, OptionSpelling::Cli);
  return w;
}

RunOptions options_from(const std::vector<std::pair<std::string, std::string>>& given) {
  RunOptions o;
  for (const auto& [name, value] : given) set_run_option(o, name, value);
  return o;
}

Mesh ico2() { return read_input_mesh(std::string(test::MESH_DIR) + "/ico2.off"); }

TEST(RunReport, AResumedRunsMeanStepIsItsOwnTimeOverItsOwnFrames) {
  const Mesh mesh = ico2();
  const RunOptions options = options_from({{"frames", "30"}});
  test::MemoryCheckpointer saver(mesh, options, 20, /*stop=*/true);
  ASSERT_EQ(run_contraction(mesh, options, nullptr, &saver).frames_run, 20);
  ASSERT_TRUE(saver.saved.has_value());
  test::MemoryCheckpointer resumer(&*saver.saved);
  const RunResult r =
      run_contraction(mesh, options_for_resume(*saver.saved, options), nullptr, &resumer);
  ASSERT_EQ(r.status, RunStatus::Completed);
  ASSERT_EQ(r.frames_run, 30);
  EXPECT_EQ(r.first_frame, 20);
  ASSERT_GT(r.wall_seconds, 0.0);
  // This process timed frames 21 to 30 only: 10 steps, not 30.
  EXPECT_DOUBLE_EQ(summary_of(options, r).numbers.at("mean_step_ms"), 1e3 * r.wall_seconds / 10.0);
  // A run not resumed divides by all its frames.
  const RunResult whole = run_contraction(mesh, options);
  EXPECT_EQ(whole.first_frame, 0);
  EXPECT_DOUBLE_EQ(summary_of(options, whole).numbers.at("mean_step_ms"),
                   1e3 * whole.wall_seconds / 30.0);
}

// The summary's options record `threads` as given (0: every usable core), so a reader could not
// tell how many threads the run had (review12); threads_used is that count: the option held to
// the CPUs this process may use.
TEST(RunReport, TheThreadsUsedAreTheOptionHeldToTheUsableCpus) {
  const RunResult r;
  for (const auto& [given, expected] :
       {std::pair<std::string, int>{"1", 1}, {"0", usable_cpus()}, {"4096", usable_cpus()}}) {
    SCOPED_TRACE("threads " + given);
    EXPECT_EQ(summary_of(options_from({{"threads", given}}), r).numbers.at("threads_used"),
              expected);
  }
}

TEST(RunReport, TheMassesRaisedForThePressureAreCountedAndManyAreAWarning) {
  // An even icosphere of 642 vertices: at -p 4 no mass is raised; at -p 20 the minimum mass for
  // the explicit pressure is above the mean, and every vertex lighter than the mean is raised
  // (sim/mass_scaling.hpp). The docs promised "the few vertices too light", and the run said
  // nothing of how many.
  const Mesh mesh = test::to_surface_mesh(test::icosphere(3));
  RunOptions o = options_from({{"frames", "1"}, {"collisions", "off"}});
  const RunResult calm = run_contraction(mesh, o);
  EXPECT_EQ(summary_of(o, calm).numbers.at("mass_scaled_vertices"), 0.0);
  EXPECT_EQ(summary_of(o, calm).numbers.at("max_mass_scale"), 1.0);
  EXPECT_TRUE(calm.warnings.empty()) << calm.warnings.front();

  o.sim.pressure = 20.0;
  const MassScaling expected = Simulator(mesh, o.sim).mass_scaling();
  ASSERT_GT(expected.raised, MASS_SCALING_NOTE_SHARE * 642);
  const RunResult r = run_contraction(mesh, o);
  const Recorder s = summary_of(o, r);
  EXPECT_EQ(s.numbers.at("mass_scaled_vertices"), static_cast<double>(expected.raised));
  EXPECT_EQ(s.numbers.at("max_mass_scale"), expected.largest_factor);
  EXPECT_GT(expected.largest_factor, 1.0);
  std::optional<std::string> note;
  for (const std::string& w : r.warnings)
    if (w.find("too light for the explicit pressure") != std::string::npos) note = w;
  ASSERT_TRUE(note.has_value());
  EXPECT_NE(note->find(std::to_string(expected.raised) + " of 642 vertices"), std::string::npos)
      << *note;
  // The step it names raises none.
  const std::string at = "At `dt` ";
  const std::size_t from = note->find(at);
  ASSERT_NE(from, std::string::npos) << *note;
  SimOptions smaller = o.sim;
  smaller.dt = std::stod(note->substr(from + at.size()));
  EXPECT_LT(smaller.dt, o.sim.dt);
  EXPECT_EQ(Simulator(mesh, smaller).mass_scaled_vertices(), 0u);
  smaller.dt *= 1.2;  // rounded down to two digits, it is close to where the first is raised
  EXPECT_GT(Simulator(mesh, smaller).mass_scaled_vertices(), 0u);
}

TEST(RunReport, TargetReachedIsNullWhenNothingWasToBeReached) {
  // A failed run without a target: "target_reached": true let it pass a filter on the key.
  const RunOptions none = options_from({{"frames", "5"}});
  RunResult failed;
  failed.status = RunStatus::SimulationFailed;
  const Recorder s = summary_of(none, failed);
  EXPECT_EQ(s.bools.count("target_reached"), 0u);
  EXPECT_EQ(s.nulls.count("target_reached"), 1u);
  // With a target or a stop ratio it says whether the run reached it.
  RunResult reached;
  reached.target_reached = false;
  for (const auto& given : {std::pair<std::string, std::string>{"target-volume", "0.8"},
                            std::pair<std::string, std::string>{"stop-volume-ratio", "0.8"}}) {
    const Recorder t = summary_of(options_from({given}), reached);
    ASSERT_EQ(t.bools.count("target_reached"), 1u) << given.first;
    EXPECT_FALSE(t.bools.at("target_reached")) << given.first;
    EXPECT_EQ(t.nulls.count("target_reached"), 0u) << given.first;
  }
}

TEST(RunReport, SliverFacesAreAWarningWhateverTheBending) {
  // math-spec 11: a rest triangle with an angle below 1 degree is warned of. Only the isometric
  // bending's clamped cotangents were, so a default run (dihedral bending) said nothing (review
  // numguards M3). A vertex of an icosphere moved 99.5 % of the way to a neighbour makes the two
  // faces on that edge slivers (angles of about 0.3 degrees opposite the short edge), far above
  // the degenerate bound; the icosphere itself has none.
  const test::TriMesh ico = test::icosphere(2);
  const RunOptions o = options_from({{"frames", "1"}, {"collisions", "off"}});
  const auto slivers = [](const RunResult& r) {
    std::size_t n = 0;
    for (const std::string& w : r.warnings)
      n += w.find("rest angle below 1 degree") != std::string::npos;
    return n;
  };
  EXPECT_EQ(slivers(run_contraction(test::to_surface_mesh(ico), o)), 0u);
  test::TriMesh thin = ico;
  const int v = thin.faces(0, 0), w = thin.faces(0, 1);
  thin.x.row(v) += 0.995 * (thin.x.row(w) - thin.x.row(v));
  for (const std::string bending : {"dihedral", "isometric"}) {
    RunOptions b = o;
    b.sim.bending = bending == "dihedral" ? BendingModel::Dihedral : BendingModel::Isometric;
    const RunResult r = run_contraction(test::to_surface_mesh(thin), b);
    ASSERT_EQ(slivers(r), 1u) << bending;
    for (const std::string& w : r.warnings)
      if (w.find("rest angle below 1 degree") != std::string::npos)
        EXPECT_EQ(w.rfind("2 faces have", 0), 0u) << w;
  }
  // Under pbd a sliver is harmless (math-spec 11: the step does not see the stiffness): no word.
  RunOptions pbd = o;
  pbd.sim.solver.kind = SolverKind::Pbd;
  EXPECT_EQ(slivers(run_contraction(test::to_surface_mesh(thin), pbd)), 0u);
}

}  // namespace
}  // namespace shellcontract
