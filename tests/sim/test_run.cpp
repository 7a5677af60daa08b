// The library's run entry point (shellcontract/run.hpp): target volume reached and held, stop ratio
// and stall handling, the observer's view of the run, cancellation, running out of memory, exit
// codes.
#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/measure.h>

#include <algorithm>
#include <cmath>
#include <new>
#include <string>
#include <vector>

#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/regions.hpp"
#include "shellcontract/run.hpp"
#include "sim/simulator.hpp"
#include "support/cgal_mesh.hpp"
#include "support/cgal_volume.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

Mesh sphere(int level = 2) { return test::to_surface_mesh(test::icosphere(level)); }

/// The target volume's acceptance tolerance (issue "Control", item 1), a number here rather than
/// the code's TARGET_VOLUME_TOLERANCE, so that widening that constant does not widen the tests.
constexpr double TARGET_TOLERANCE = 0.005;

/// Records what the run shows it.
struct Recorder final : RunObserver {
  int n_started = 0, n_finished = 0;
  std::vector<int> frames;
  std::vector<double> ratios;
  std::vector<std::string> warnings;
  int cancel_at = -1;
  void warning(const std::string& w) override { warnings.push_back(w); }
  void started(const FrameView& view) override {
    ++n_started;
    EXPECT_EQ(view.frame(), 0);
  }
  void frame(const FrameView&, const FrameMetrics& m) override {
    frames.push_back(m.frame);
    ratios.push_back(m.volume_ratio);
  }
  bool cancelled() override {
    return cancel_at >= 0 && static_cast<int>(frames.size()) >= cancel_at;
  }
  void finished(const FrameView&, const RunResult&) override { ++n_finished; }
};

TEST(Run, TargetVolumeIsReachedAndHeldOnASphere) {
  for (double target : {0.9, 0.5, 0.3}) {  // 1 - (1 - 0.3) is not 0.3 in doubles
    RunOptions o;
    o.sim.frames = 120;
    o.sim.target_volume = target;
    o.sim.target_ramp_frames = 40;
    Recorder rec;
    const RunResult r = run_contraction(sphere(3), o, &rec);
    EXPECT_EQ(r.status, RunStatus::Completed) << r.message;
    EXPECT_TRUE(r.target_reached);
    EXPECT_EQ(r.exit_code(), 0);
    ASSERT_EQ(rec.ratios.size(), 120u);
    // Held over the last half, after the ramp, within the documented tolerance.
    for (std::size_t i = 60; i < rec.ratios.size(); ++i)
      EXPECT_NEAR(rec.ratios[i], target, TARGET_TOLERANCE) << "frame " << i + 1;
    // The result itself, in the input's units, measured with CGAL rather than by the run.
    EXPECT_NEAR(test::cgal_volume_ratio(sphere(3), r.positions), target, TARGET_TOLERANCE);
    EXPECT_GE(r.frame_target_reached, 40);
    EXPECT_LE(r.frame_target_reached, 60);
  }
}

TEST(Run, TargetVolumeHoldsAgainstAPressureThatWouldContractFurther) {
  // Without the constraint, P = 20 takes the sphere to about 0.9 in 80 frames; with it, V/V0
  // holds at 0.97: the constraint pushes back against the pressure, not only along with it.
  RunOptions free;
  free.sim.frames = 80;
  free.sim.pressure = 20.0;
  free.sim.collisions = false;
  const RunResult crushed = run_contraction(sphere(2), free);
  ASSERT_LT(crushed.final_volume_ratio, 0.95);
  RunOptions held = free;
  held.sim.target_volume = 0.97;
  const RunResult r = run_contraction(sphere(2), held);
  EXPECT_NEAR(r.final_volume_ratio, 0.97, TARGET_TOLERANCE);
  EXPECT_NEAR(test::cgal_volume_ratio(sphere(2), r.positions), 0.97, TARGET_TOLERANCE);
  EXPECT_EQ(r.status, RunStatus::Completed);
}

TEST(Run, StopRatioEndsAtTheCrossingFrame) {
  RunOptions o;
  o.sim.frames = 2000;
  o.sim.pressure = 3.0;
  o.sim.air_balance = 0.0;  // constant pressure: nothing stops the shell before the crossing
  o.sim.stop_volume_ratio = 0.8;
  const RunResult r = run_contraction(sphere(3), o);
  EXPECT_EQ(r.status, RunStatus::Completed) << r.message;
  EXPECT_NEAR(r.final_volume_ratio, 0.8, 0.002);
  EXPECT_EQ(r.frame_target_reached, r.frames_run);
  EXPECT_LT(r.frames_run, 2000);
}

TEST(Run, AStalledVolumeStopsTheRunWithExitCode5) {
  // No pressure: the volume never moves toward the stop ratio, so the run stops once it has
  // stalled for STALL_FRAMES frames instead of running all 1000.
  RunOptions o;
  o.sim.frames = 1000;
  o.sim.pressure = 0.0;
  o.sim.bending = BendingModel::None;  // the flat-rest bending would inflate the curved shell
  o.sim.stop_volume_ratio = 0.5;
  Recorder rec;
  const RunResult r = run_contraction(sphere(2), o, &rec);
  EXPECT_EQ(r.status, RunStatus::TargetNotReached);
  EXPECT_EQ(r.exit_code(), static_cast<int>(ExitCode::TargetNotReached));
  EXPECT_EQ(r.exit_code(), 5);
  EXPECT_FALSE(r.target_reached);
  EXPECT_EQ(r.frames_run, STALL_FRAMES);  // frame 0 and frame 20 differ by less than 1e-4
  EXPECT_NE(r.message.find("stalled"), std::string::npos) << r.message;
  EXPECT_EQ(rec.n_finished, 1);
}

TEST(Run, ASmallTargetIsNotReachedByACollapseFarBelowIt) {
  // docs/math/volume-control.md, section 4: |V/V0 - R| <= min(0.005, 0.05 R), written out here
  // as numbers. An absolute 0.005 alone took V/V0 7e-8 (a collapsed shell) as reaching R = 0.001.
  EXPECT_FALSE(target_volume_reached(7e-8, 0.001));
  EXPECT_FALSE(target_volume_reached(0.0, 0.001));
  EXPECT_FALSE(target_volume_reached(0.006, 0.001));
  EXPECT_TRUE(target_volume_reached(0.00104, 0.001));  // 5 % of R: 5e-5
  EXPECT_TRUE(target_volume_reached(0.00096, 0.001));
  EXPECT_FALSE(target_volume_reached(0.00106, 0.001));
  EXPECT_FALSE(target_volume_reached(0.00094, 0.001));
  EXPECT_TRUE(target_volume_reached(0.0209, 0.02));
  EXPECT_FALSE(target_volume_reached(0.0227, 0.02));  // 13 % above R
  // From R = 0.1 up the tolerance is the absolute 0.005 it always was.
  EXPECT_TRUE(target_volume_reached(0.1049, 0.1));
  EXPECT_FALSE(target_volume_reached(0.1051, 0.1));
  EXPECT_TRUE(target_volume_reached(0.3049, 0.3));
  EXPECT_TRUE(target_volume_reached(0.5004, 0.5));
  EXPECT_TRUE(target_volume_reached(0.4951, 0.5));
  EXPECT_FALSE(target_volume_reached(0.5051, 0.5));
  EXPECT_FALSE(target_volume_reached(0.4949, 0.5));
  EXPECT_TRUE(target_volume_reached(1.9951, 2.0));  // a keyframe may inflate to 2
  EXPECT_FALSE(target_volume_reached(1.9949, 2.0));
  // A non-finite volume reaches nothing.
  EXPECT_FALSE(target_volume_reached(std::nan(""), 0.5));
  EXPECT_FALSE(target_volume_reached(HUGE_VAL, 0.5));
}

TEST(Run, ACollapseFarBelowASmallTargetEndsWithExitCode5) {
  // ico1 collapses to V/V0 below 1e-6 when driven to 0.001 in 6 frames; within the old absolute
  // 0.005 of the target, this ended with exit 0. The message says how far off it is.
  RunOptions o;
  o.sim.frames = 6;
  o.sim.target_volume = 0.001;
  const RunResult r = run_contraction(sphere(1), o);
  ASSERT_LT(r.final_volume_ratio, 0.0005) << "the premise: the shell collapses far below R";
  EXPECT_EQ(r.status, RunStatus::TargetNotReached) << r.message;
  EXPECT_FALSE(r.target_reached);
  EXPECT_EQ(r.exit_code(), 5);
  EXPECT_NE(r.message.find("target volume 0.001 not reached"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("times smaller than the target"), std::string::npos) << r.message;
  EXPECT_EQ(r.frame_target_reached, -1);
}

TEST(Run, FramesRunningOutBeforeTheStopRatioIsReported) {
  RunOptions o;
  o.sim.frames = 5;
  o.sim.pressure = 1.0;
  o.sim.stop_volume_ratio = 0.5;
  const RunResult r = run_contraction(sphere(2), o);
  EXPECT_EQ(r.status, RunStatus::TargetNotReached);
  EXPECT_NE(r.message.find("frames ran out"), std::string::npos) << r.message;
  EXPECT_EQ(r.frames_run, 5);
}

TEST(Run, ObserverSeesEveryFrameAndCanCancel) {
  RunOptions o;
  o.sim.frames = 12;
  Recorder all;
  const RunResult r = run_contraction(sphere(2), o, &all);
  EXPECT_EQ(all.n_started, 1);
  EXPECT_EQ(all.n_finished, 1);
  ASSERT_EQ(all.frames.size(), 12u);
  for (int i = 0; i < 12; ++i) EXPECT_EQ(all.frames[static_cast<std::size_t>(i)], i + 1);
  EXPECT_EQ(r.final_volume_ratio, all.ratios.back());

  Recorder cancel;
  cancel.cancel_at = 4;
  const RunResult c = run_contraction(sphere(2), o, &cancel);
  EXPECT_EQ(c.status, RunStatus::Cancelled);
  EXPECT_EQ(c.frames_run, 4);
  EXPECT_EQ(c.exit_code(), static_cast<int>(ExitCode::Cancelled));
}

TEST(Run, ResultEqualsTheSimulatorStepByStep) {
  // The entry point adds no physics of its own: the same positions as a bare Simulator loop.
  RunOptions o;
  o.sim.frames = 15;
  resolve_run_options(o);
  const Mesh mesh = sphere(2);
  Simulator sim(mesh, o.sim);
  while (!sim.finished()) sim.step();
  const RunResult r = run_contraction(mesh, o);
  EXPECT_EQ(r.positions, sim.positions_in_input_units());
}

/// Throws std::bad_alloc where an observer that keeps frames would run out of memory.
struct ExhaustedObserver final : RunObserver {
  int throw_at_frame = -1;  ///< frame() throws at this frame
  bool throw_at_finish = false;
  int n_finished = 0;
  void frame(const FrameView&, const FrameMetrics& m) override {
    if (m.frame == throw_at_frame) throw std::bad_alloc();
  }
  void finished(const FrameView&, const RunResult&) override {
    ++n_finished;
    if (throw_at_finish) throw std::bad_alloc();
  }
};

TEST(Run, OutOfMemoryEndsTheRunWithTheLastGoodState) {
  // A run that memory fails returns, with the state of its last whole step: the same positions
  // as a run asked for that many frames (the CLI writes them, exit code 3).
  RunOptions o;
  o.sim.frames = 12;
  RunOptions five = o;
  five.sim.frames = 5;
  const Mesh mesh = sphere(2);
  const RunResult ref = run_contraction(mesh, five);
  ExhaustedObserver obs;
  obs.throw_at_frame = 5;
  RunResult r;
  ASSERT_NO_THROW(r = run_contraction(mesh, o, &obs));
  EXPECT_EQ(r.status, RunStatus::SimulationFailed);
  EXPECT_EQ(r.exit_code(), static_cast<int>(ExitCode::SimulationFailed));
  EXPECT_NE(r.message.find("out of memory after step 5"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find(std::to_string(mesh.number_of_faces()) + " faces"), std::string::npos)
      << r.message;
  EXPECT_EQ(r.frames_run, 5);
  EXPECT_EQ(r.positions, ref.positions);
  EXPECT_EQ(obs.n_finished, 1);

  // In the observers' end: the run is whole, and says it failed.
  const RunResult full = run_contraction(mesh, o);
  ExhaustedObserver at_end;
  at_end.throw_at_finish = true;
  ASSERT_NO_THROW(r = run_contraction(mesh, o, &at_end));
  EXPECT_EQ(r.status, RunStatus::SimulationFailed);
  EXPECT_NE(r.message.find("out of memory after the last step"), std::string::npos) << r.message;
  EXPECT_EQ(r.frames_run, 12);
  EXPECT_EQ(r.positions, full.positions);
}

TEST(Run, AnisoWithoutRegionsWarns) {
  RunOptions o;
  o.sim.frames = 2;
  set_run_option(o, "aniso", "arap");
  set_run_option(o, "regions", "none");
  Recorder rec;
  const RunResult r = run_contraction(sphere(2), o, &rec);
  ASSERT_EQ(rec.warnings.size(), 1u);
  EXPECT_NE(rec.warnings[0].find("no effect"), std::string::npos);
  EXPECT_EQ(r.warnings, rec.warnings);
}

}  // namespace
}  // namespace shellcontract

namespace shellcontract {
namespace {

TEST(Run, OptionsWithoutEffectAreWarnedAndDefaultsAreNot) {
  RunOptions quiet;
  quiet.sim.frames = 1;
  Recorder none;
  run_contraction(sphere(1), quiet, &none);
  EXPECT_TRUE(none.warnings.empty());
  RunOptions o;
  o.sim.frames = 1;
  set_run_option(o, "c10", "0.7");  // StVK is the material
  set_run_option(o, "collisions", "off");
  set_run_option(o, "delta", "0.001");        // collisions are off
  set_run_option(o, "region-shrink", "0.5");  // no --regions
  set_run_option(o, "pressure", "2");         // effective: no target volume
  Recorder rec;
  const RunResult r = run_contraction(sphere(1), o, &rec);
  ASSERT_EQ(rec.warnings.size(), 3u);
  EXPECT_NE(rec.warnings[0].find("`region_shrink`"), std::string::npos) << rec.warnings[0];
  EXPECT_NE(rec.warnings[1].find("`c10`"), std::string::npos) << rec.warnings[1];
  EXPECT_NE(rec.warnings[2].find("`delta`"), std::string::npos) << rec.warnings[2];
  EXPECT_EQ(r.warnings, rec.warnings);
}

/// Area of each region of the mesh's f:region map, as a fraction of the whole surface.
std::vector<double> region_area_fractions(const Mesh& mesh) {
  const std::vector<int> region = stored_regions(mesh);
  std::vector<double> area;
  double total = 0.0;
  for (FaceIndex f : mesh.faces()) {
    const double a = CGAL::Polygon_mesh_processing::face_area(f, mesh);
    total += a;
    if (region[f.idx()] < 0) continue;
    const std::size_t r = static_cast<std::size_t>(region[f.idx()]);
    if (area.size() <= r) area.resize(r + 1, 0.0);
    area[r] += a;
  }
  for (double& a : area) a /= total;
  return area;
}

// --region-max-area bounds the regions that --regions auto keeps: on bumpy_sphere, whose bumps
// differ in size, every kept region is within the bound and a tighter bound keeps no more.
TEST(Run, RegionMaxAreaDropsTheLargerAutoRegions) {
  const Mesh input = read_input_mesh(std::string(test::MESH_DIR) + "/bumpy_sphere.off");
  std::size_t previous = 0;
  double largest = 0.0;
  for (const char* bound : {"0.5", "0.08", "0.03"}) {
    RunOptions o;
    set_run_option(o, "regions", "auto");
    set_run_option(o, "region-max-area", bound);
    Mesh mesh = input;
    const std::size_t count = mark_run_regions(mesh, o);
    const std::vector<double> area = region_area_fractions(mesh);
    ASSERT_EQ(area.size(), count) << bound;
    for (double a : area) EXPECT_LE(a, std::stod(bound)) << bound;
    if (previous > 0) {
      EXPECT_LE(count, previous) << bound;
    }
    if (previous == 0)
      for (double a : area) largest = std::max(largest, a);
    previous = count;
  }
  // The bounds straddle at least the largest region, so something was dropped.
  ASSERT_GT(largest, 0.03);
  RunOptions all;
  set_run_option(all, "regions", "auto");
  Mesh mesh = input;
  EXPECT_GT(mark_run_regions(mesh, all), previous);
}

TEST(Run, RegionMaxAreaWithoutAutoRegionsIsWarned) {
  RunOptions o;
  o.sim.frames = 1;
  set_run_option(o, "region-max-area", "0.05");
  Recorder rec;
  run_contraction(sphere(1), o, &rec);
  ASSERT_EQ(rec.warnings.size(), 1u);
  EXPECT_NE(rec.warnings[0].find("`region_max_area`"), std::string::npos) << rec.warnings[0];
}

TEST(Run, OrderAutoIsColouredAtEverySizeAndSequentialOnRequest) {
  EXPECT_EQ(order_for(OrderChoice::Auto), ConstraintOrder::Coloured);
  EXPECT_EQ(order_for(OrderChoice::Coloured), ConstraintOrder::Coloured);
  EXPECT_EQ(order_for(OrderChoice::Sequential), ConstraintOrder::Sequential);
  // The run reports the order it used: coloured by default on a small sphere, the paper's
  // sequential order when asked.
  RunOptions o;
  o.sim.frames = 0;
  o.sim.collisions = false;
  EXPECT_EQ(run_contraction(sphere(2), o).order, ConstraintOrder::Coloured);
  set_run_option(o, "order", "sequential");
  EXPECT_EQ(run_contraction(sphere(2), o).order, ConstraintOrder::Sequential);
  set_run_option(o, "order", "auto");
  EXPECT_EQ(run_contraction(sphere(2), o).order, ConstraintOrder::Coloured);
}

TEST(Run, ResolvedOptionsRecordTheChoiceAutoMade) {
  // The summary, a checkpoint and a sweep's job id write the options' text: "auto" had stayed
  // "auto", so a sweep ran the default and --order coloured as two jobs of one run, and a resume
  // with --order coloured was refused ("the checkpoint's: auto").
  const auto text = [](const std::vector<std::pair<std::string, std::string>>& given) {
    RunOptions o;
    for (const auto& [name, value] : given) set_run_option(o, name, value);
    resolve_run_options(o);
    std::vector<std::string> all;
    for (const OptionSpec& spec : run_option_table()) all.push_back(spec.name + "=" + spec.get(o));
    return all;
  };
  const auto value = [](const std::vector<std::string>& all, const std::string& name) {
    for (const std::string& s : all)
      if (s.rfind(name + "=", 0) == 0) return s.substr(name.size() + 1);
    return std::string("(none)");
  };
  const std::vector<std::string> defaults = text({});
  EXPECT_EQ(value(defaults, "order"), "coloured");
  EXPECT_EQ(value(defaults, "speculative-broad-phase"), "off");
  EXPECT_EQ(defaults, text({{"order", "coloured"}, {"speculative-broad-phase", "off"}}));
  EXPECT_EQ(defaults, text({{"order", "auto"}, {"speculative-broad-phase", "auto"}}));
  const std::vector<std::string> paper = text({{"order", "sequential"}});
  EXPECT_EQ(value(paper, "speculative-broad-phase"), "on");
  EXPECT_EQ(paper, text({{"order", "sequential"}, {"speculative-broad-phase", "on"}}));
  EXPECT_EQ(value(text({{"order", "sequential"}, {"speculative-broad-phase", "off"}}),
                  "speculative-broad-phase"),
            "off");
  // Resolving twice changes nothing (a checkpoint's options are resolved again on resume).
  RunOptions twice;
  resolve_run_options(twice);
  resolve_run_options(twice);
  EXPECT_EQ(twice.order, OrderChoice::Coloured);
  EXPECT_EQ(twice.sim.speculative_broad_phase, SpeculativeBroadPhase::Off);
  EXPECT_FALSE(twice.sim.collision.speculative);
}

}  // namespace
}  // namespace shellcontract
