// The run plan (sim/run_plan.hpp): the one place where the options are resolved and checked and
// the regions become the mesh's f:region map; option fields in the library's messages and each
// front end's spelling of them; the summary and log row written once for the CLI and Python
// (shellcontract/report.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "mesh/eigen_point_map.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/regions.hpp"
#include "shellcontract/report.hpp"
#include "shellcontract/run.hpp"
#include "sim/run_plan.hpp"
#include "support/cgal_mesh.hpp"

namespace shellcontract {
namespace {

Mesh sphere(int level = 2) { return test::to_surface_mesh(test::icosphere(level)); }

std::string what_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const UsageError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(RunPlan, ShellMaterialGivesMuLambdaAndKbInClosedForm) {
  // The default run: XPBD, E = 1000, nu = 0.3, h = 0.002, dihedral bending. Plane-stress Lame
  // parameters and the plate's k_B = D / 3 = E h^3 / (36 (1 - nu^2)), written out here.
  const RunPlan plan = plan_run(sphere(1), RunOptions{});
  const double E = DEFAULT_SHELL_YOUNG, h = DEFAULT_SHELL_THICKNESS, nu = 0.3;
  const SimOptions& s = plan.sim.options;
  EXPECT_NEAR(s.material_params.mu, E * h / (2.0 * (1.0 + nu)), 1e-14);
  EXPECT_NEAR(s.material_params.lambda, E * h * nu / (1.0 - nu * nu), 1e-14);
  EXPECT_NEAR(s.solver.k_bending, E * h * h * h / (36.0 * (1.0 - nu * nu)), 1e-18);
  // Derived values the Simulator no longer derives itself: the time step the solver's compliance
  // reads, and mu_A for k_A, each given at a value other than its default (both defaults agree
  // with the solver's and the anisotropy's own, so the defaults alone cannot tell).
  EXPECT_EQ(s.solver.dt, s.dt);
  RunOptions stepped;
  set_run_option(stepped, "dt", "0.005");
  set_run_option(stepped, "mu-a", "20");
  const SimOptions& t = plan_run(sphere(1), stepped).sim.options;
  EXPECT_EQ(t.solver.dt, 0.005);
  EXPECT_EQ(t.anisotropy.mu_aniso, 20.0);
  EXPECT_EQ(plan.options.sim.material_params.mu, s.material_params.mu);
  // k_B given is kept: the material derives it only where the caller left it.
  RunOptions given;
  set_run_option(given, "k-b", "0.02");
  EXPECT_EQ(plan_run(sphere(1), given).sim.options.solver.k_bending, 0.02);
}

TEST(RunPlan, StiffnessesThatWouldOverflowAreRefusedNamingWhatSetThem) {
  // A stiffness of 1e200 ran as if the membrane had none (its squares overflow in the energies
  // and compliances), and --thickness 1e102 was refused as "--k-b must be >= 0", an option not
  // given. Every stiffness is now at most MAX_STIFFNESS (1e100), and the shell material's are
  // refused under its own options.
  for (const char* name : {"mu", "lambda", "c10", "c01", "mu-a", "k-b", "k-a"}) {
    RunOptions huge;
    set_run_option(huge, name, "1e200");
    const std::string m = spell_options(what_of([&] { plan_run(sphere(1), huge); }), OptionSpelling::Cli);
    EXPECT_NE(m.find(std::string("--") + name + " must be at most 1e+100"), std::string::npos) << m;
    RunOptions fine;
    set_run_option(fine, name, "1e90");
    EXPECT_NO_THROW(plan_run(sphere(1), fine)) << name;
  }
  for (const auto& [name, value] : {std::pair<const char*, const char*>{"young", "1e200"}, {"thickness", "1e102"}}) {
    RunOptions shell;
    set_run_option(shell, name, value);
    const std::string m = spell_options(what_of([&] { plan_run(sphere(1), shell); }), OptionSpelling::Cli);
    EXPECT_NE(m.find("--young"), std::string::npos) << m;
    EXPECT_NE(m.find("--thickness"), std::string::npos) << m;
    EXPECT_NE(m.find("at most 1e+100"), std::string::npos) << m;
  }
}

TEST(RunPlan, TimeStepsWhoseSquareUnderflowsAreRefused) {
  // XPBD divides by dt^2: --dt 1e-155 gave NaN positions at the first step. The smallest step
  // MIN_DT keeps 1 / dt^2 finite and still runs.
  SimOptions tiny;
  tiny.dt = 1e-155;
  // Refused as the option table refuses the text (sim/option_ranges.hpp), naming its bound.
  const std::string m = what_of([&] { plan_simulation(sphere(1), tiny); });
  EXPECT_EQ(m.rfind("`dt`: '1e-155' is not", 0), 0u) << m;
  EXPECT_NE(m.find("[1e-100, "), std::string::npos) << m;
  RunOptions smallest;
  set_run_option(smallest, "dt", "1e-100");
  set_run_option(smallest, "frames", "2");
  const RunResult r = run_contraction(sphere(1), smallest);
  EXPECT_EQ(r.status, RunStatus::Completed) << r.message;
  EXPECT_TRUE(std::isfinite(r.final_volume_ratio));
}

TEST(RunPlan, RegionFileBecomesTheRegionMapOfTheNormalizedMesh) {
  const Mesh mesh = sphere(2);
  const std::string path = ::testing::TempDir() + "run_plan_regions.txt";
  {
    std::ofstream out(path);
    out << "7 3 5\n40 41\n";
  }
  RunOptions o;
  set_run_option(o, "regions", path);
  const RunPlan plan = plan_run(mesh, o);
  EXPECT_EQ(plan.regions, 2u);
  EXPECT_EQ(stored_regions(plan.sim.mesh),
            face_ids_from_regions({{7, 3, 5}, {40, 41}}, mesh.number_of_faces()));
  // The plan's mesh is normalized: bounding-box diagonal 1.
  const Positions x = positions_from_mesh(plan.sim.mesh);
  EXPECT_NEAR((x.colwise().maxCoeff() - x.colwise().minCoeff()).norm(), 1.0, 1e-12);
  // No region source: every face -1, whatever map the caller's mesh had.
  Mesh marked = mesh;
  store_regions(marked, face_ids_from_regions({{1, 2}}, mesh.number_of_faces()));
  const RunPlan none = plan_run(marked, RunOptions{});
  EXPECT_EQ(none.regions, 0u);
  EXPECT_EQ(stored_regions(none.sim.mesh), std::vector<int>(mesh.number_of_faces(), -1));
  std::remove(path.c_str());
}

TEST(RunPlan, RulesNameTheFieldsAndEachFrontEndSpellsThem) {
  RunOptions both;
  set_run_option(both, "target-volume", "0.5");
  set_run_option(both, "stop-volume-ratio", "0.3");
  const std::string m = what_of([&] { plan_run(sphere(1), both); });
  EXPECT_EQ(m.rfind("`target_volume` and `stop_volume_ratio` exclude each other", 0), 0u) << m;
  EXPECT_EQ(spell_options(m, OptionSpelling::Cli)
                .rfind("--target-volume and --stop-volume-ratio exclude each other", 0),
            0u);
  EXPECT_EQ(spell_options(m, OptionSpelling::Python)
                .rfind("target_volume and stop_volume_ratio exclude each other", 0),
            0u);
  // The same rule, and the same message, for a Simulator built from SimOptions alone: one
  // check, reached from both entry points.
  SimOptions s;
  s.target_volume = 0.5;
  s.stop_volume_ratio = 0.3;
  EXPECT_EQ(what_of([&] { plan_simulation(sphere(1), s); }), m);
  // The k_B bound of pbd, where k_B is a correction multiplier.
  RunOptions stiff;
  set_run_option(stiff, "solver", "pbd");
  set_run_option(stiff, "k-b", "2");
  EXPECT_EQ(what_of([&] { resolve_run_options(stiff); }).rfind("`k_b`: in pbd mode", 0), 0u);
  SimOptions pbd;
  pbd.solver.k_bending = 2.0;
  EXPECT_EQ(what_of([&] { plan_simulation(sphere(1), pbd); }).rfind("`k_b`: in pbd mode", 0), 0u);
}

// A C++ caller that writes RunOptions' fields is held to the option table's ranges
// (docs/design/run-plan.md: "a caller that writes the fields is held by the same checks"). The
// values the table was made to refuse (OptionTable.RangesFromTheIssue) were accepted when written
// on the struct: mu = -1 or NaN ran a default run as if the membrane were not there, density = inf
// ended at V/V0 1 with status ok, delta = 0.5 inflated the shell, keyframes out of order ran.
TEST(RunPlan, FieldsWrittenOutsideTheTableAreHeldToItsRanges) {
  const double nan = std::nan("");
  const std::vector<std::pair<std::string, std::function<void(RunOptions&)>>> cases = {
      {"mu", [](RunOptions& o) { o.sim.material_params.mu = -1.0; }},
      {"mu", [&](RunOptions& o) { o.sim.material_params.mu = nan; }},
      {"lambda", [&](RunOptions& o) { o.sim.material_params.lambda = nan; }},
      // Negative down to -mu is a material (a Poisson ratio above -1); at -mu it is not.
      {"lambda", [](RunOptions& o) { o.sim.material_params.lambda = -1.0; }},
      {"c10", [](RunOptions& o) { o.sim.material_params.c10 = -1.0; }},
      {"c01", [&](RunOptions& o) { o.sim.material_params.c01 = nan; }},
      {"density", [](RunOptions& o) { o.sim.density = INFINITY; }},
      {"mu_a", [](RunOptions& o) { o.sim.material_params.mu_aniso = -1.0; }},
      {"k_a", [&](RunOptions& o) { o.sim.anisotropy.kappa_a = nan; }},
      {"fiber_target", [](RunOptions& o) { o.sim.material_params.fiber_target = 2.0; }},
      {"delta", [](RunOptions& o) { o.sim.collision.delta = 0.5; }},
      {"fiber", [](RunOptions& o) {
         o.sim.anisotropy.fiber_mode = FiberMode::User;
         o.sim.anisotropy.user_direction = Vec3::Zero();
       }},
      {"pressure", [](RunOptions& o) {
         o.sim.pressure_schedule = Schedule({{0, 4.0}, {20, 1.0}, {10, 2.0}});
         o.sim.pressure = 4.0;
       }},
      {"target_volume", [](RunOptions& o) {
         o.sim.target_volume_schedule = Schedule({{0, 1.0}, {10, 0.7}, {10, 0.9}});
         o.sim.target_volume = 0.9;
       }},
      {"material", [](RunOptions& o) { o.sim.material = static_cast<MaterialKind>(42); }},
      {"regions", [](RunOptions& o) { o.regions = RegionSource::File; }},  // no file named
      // The shell material's values had been refused by the function that converts them
      // ("membrane_lame_from_young: need E > 0 ..."), naming no option; weights as the region
      // source with none given had the run open a weight file with no name (an InputError).
      {"young", [](RunOptions& o) { o.young = -1.0; }},
      {"young", [&](RunOptions& o) { o.young = nan; }},
      {"thickness", [](RunOptions& o) { o.thickness = 0.0; }},
      {"poisson", [&](RunOptions& o) { o.poisson = nan; }},
      {"regions", [](RunOptions& o) { o.regions = RegionSource::Weights; }},
  };
  for (const auto& [field, write] : cases) {
    RunOptions o;
    o.sim.frames = 5;
    write(o);
    const std::string m = what_of([&] { run_contraction(sphere(1), o); });
    EXPECT_EQ(m.rfind("`" + field + "`", 0), 0u) << field << ": " << m;
  }
  // Values the table accepts still run, written on the struct: a negative Poisson ratio (whose
  // resolved lambda is negative), the paper's pbd settings, a schedule in order.
  RunOptions fine;
  fine.sim.frames = 3;
  fine.poisson = -0.5;
  EXPECT_NO_THROW(run_contraction(sphere(1), fine));
  RunOptions resolved = fine;
  resolve_run_options(resolved);
  EXPECT_LT(resolved.sim.material_params.lambda, 0.0);
  EXPECT_NO_THROW(resolve_run_options(resolved));  // idempotent
  fine.sim.solver.kind = SolverKind::Pbd;
  fine.sim.pressure_schedule = Schedule({{0, 4.0}, {10, 2.0}});
  EXPECT_NO_THROW(run_contraction(sphere(1), fine));
}

// Separate shells share the air, the target and the stop ratio (the whole's volume): the review's
// two balls ended at 0.607 and 0.359 of their volumes under a target of 0.6, without a word.
TEST(RunPlan, SeparateComponentsSharingTheVolumeAreAWarning) {
  const test::TriMesh ball = test::icosphere(1);
  test::TriMesh two;
  two.x.resize(2 * ball.x.rows(), 3);
  two.x << ball.x, (ball.x * 0.3).rowwise() + Eigen::RowVector3d(3.0, 0.0, 0.0);
  two.faces.resize(2 * ball.faces.rows(), 3);
  two.faces << ball.faces, ball.faces.array() + static_cast<int>(ball.x.rows());
  const auto warned = [](const RunPlan& plan, const std::string& text) {
    return std::any_of(plan.warnings.begin(), plan.warnings.end(),
                       [&](const std::string& w) { return w.find(text) != std::string::npos; });
  };
  RunOptions target;
  set_run_option(target, "target-volume", "0.6");
  set_run_option(target, "air-balance", "0");
  EXPECT_TRUE(
      warned(plan_run(test::to_surface_mesh(two), target),
             "the mesh has 2 separate components: the target volume acts on their total volume"));
  RunOptions air;  // the defaults: a pressure against the enclosed air
  EXPECT_TRUE(warned(plan_run(test::to_surface_mesh(two), air),
                     "the enclosed air acts on their total volume"));
  RunOptions neither;  // a pressure with no air: each shell on its own
  set_run_option(neither, "air-balance", "0");
  EXPECT_FALSE(warned(plan_run(test::to_surface_mesh(two), neither), "separate components"));
  EXPECT_FALSE(warned(plan_run(test::to_surface_mesh(ball), target), "separate components"));
}

TEST(RunPlan, GivenRecordsFieldNamesNotFlags) {
  RunOptions o;
  set_run_option(o, "k-b", "0.02");
  set_run_option(o, "region_shrink", "0.5");  // Python's spelling is accepted too
  EXPECT_EQ(o.given, (std::set<std::string>{"k_b", "region_shrink"}));
}

TEST(RunPlan, DefaultRegionMaxAreaIsTheRegionFindersDefault) {
  EXPECT_EQ(RunOptions{}.region_max_area, RegionOptions{}.max_area_fraction);
}

TEST(SpellOptions, SpellsOnlyTheTablesFields) {
  const std::string m = "a `b` c `k_b` and `nonsense`, `region_max_area` --x `";
  EXPECT_EQ(spell_options(m, OptionSpelling::Cli),
            "a `b` c --k-b and `nonsense`, --region-max-area --x `");
  EXPECT_EQ(spell_options(m, OptionSpelling::Python),
            "a `b` c k_b and `nonsense`, region_max_area --x `");
  EXPECT_EQ(spell_options("no fields here", OptionSpelling::Cli), "no fields here");
}

TEST(RunReport, LogLineReadsBackAndWritesWholeNumbersAsIntegers) {
  FrameMetrics m;
  m.frame = 12;
  m.time = 0.1 + 0.2;
  m.volume_ratio = 2.0 / 3.0;
  m.collision.pairs_broad = 123456789;
  m.new_intersections = -1;
  const LogRow row = log_row(m);
  const std::string line = log_csv_line(row);
  ASSERT_EQ(line.back(), '\n');
  std::vector<std::string> fields;
  std::string field;
  for (char c : line.substr(0, line.size() - 1)) {
    if (c == ',') {
      fields.push_back(field);
      field.clear();
    } else {
      field += c;
    }
  }
  fields.push_back(field);
  ASSERT_EQ(fields.size(), LOG_COLUMN_COUNT);
  for (std::size_t c = 0; c < LOG_COLUMN_COUNT; ++c) {
    EXPECT_EQ(std::strtod(fields[c].c_str(), nullptr), row[c]) << LOG_COLUMNS[c];
    if (LOG_INTEGER[c]) {
      EXPECT_EQ(fields[c].find_first_of(".e"), std::string::npos) << fields[c];
    }
  }
  EXPECT_EQ(fields[0], "12");
  EXPECT_EQ(fields[10], "123456789");
  EXPECT_EQ(fields[14], "-1");
  EXPECT_EQ(log_csv_header().substr(0, 6), "frame,");
}

/// Keys as a SummaryWriter receives them, nested ones as "outer.inner".
class KeyRecorder final : public SummaryWriter {
 public:
  explicit KeyRecorder(std::vector<std::string>& keys, std::string prefix = "")
      : keys_(keys), prefix_(std::move(prefix)) {}
  void add_bool(const std::string& k, bool) override { keys_.push_back(prefix_ + k); }
  void add_integer(const std::string& k, long long) override { keys_.push_back(prefix_ + k); }
  void add_number(const std::string& k, double) override { keys_.push_back(prefix_ + k); }
  void add_text(const std::string& k, const std::string&) override { keys_.push_back(prefix_ + k); }
  void add_texts(const std::string& k, const std::vector<std::string>&) override {
    keys_.push_back(prefix_ + k);
  }
  void add_object(const std::string& k, const std::function<void(SummaryWriter&)>& fill) override {
    keys_.push_back(prefix_ + k);
    KeyRecorder inner(keys_, prefix_ + k + ".");
    fill(inner);
  }

 private:
  std::vector<std::string>& keys_;
  std::string prefix_;
};

bool has(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

TEST(RunReport, SummaryNamesTheOptionsInEachFrontEndsSpelling) {
  const RunOptions options;
  const RunResult r;
  const InputReport report;
  std::vector<std::string> cli, python;
  KeyRecorder c(cli), p(python);
  const SummaryFiles files{"in.off", "out.off", std::nullopt};
  write_run_summary(c, report, options, r, OptionSpelling::Cli, &files);
  write_run_summary(p, report, options, r, OptionSpelling::Python);
  EXPECT_TRUE(has(cli, "options.k-b") && has(cli, "options.stop-volume-ratio"));
  EXPECT_TRUE(has(python, "options.k_b") && has(python, "options.stop_volume_ratio"));
  EXPECT_FALSE(has(python, "input") || has(python, "output"));
  // The CLI's files come right after the exit code; otherwise the keys are the same, in order.
  ASSERT_GE(cli.size(), 5u);
  EXPECT_EQ(std::vector<std::string>(cli.begin(), cli.begin() + 5),
            (std::vector<std::string>{"status", "failure", "exit_code", "input", "output"}));
  std::vector<std::string> without_files;
  for (const std::string& k : cli)
    if (k != "input" && k != "output") without_files.push_back(k.rfind("options.", 0) == 0 ? option_field(k) : k);
  EXPECT_EQ(without_files, python);
}

}  // namespace
}  // namespace shellcontract
