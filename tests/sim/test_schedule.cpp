// Keyframed values (shellcontract/simulation_options.hpp, docs/design/keyframes.md): the curve's
// closed forms and invariants, the parser's messages, the option table's two forms, and whole runs
// that follow a volume and a pressure schedule, measured with CGAL on the positions.
#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/measure.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"
#include "shellcontract/simulation_options.hpp"
#include "sim/simulator.hpp"
#include "sim/volume_constraint.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

const KeyRange RATIO{0.0, MAX_KEYED_VOLUME_RATIO, true, false, "a ratio in (0, 2]"};
const KeyRange ANY{-1e6, 1e6, false, false, "a number"};

std::string usage_message(const std::string& option, const std::string& text) {
  try {
    if (option == "target-volume")
      parse_volume_schedule(option, text, RATIO);
    else
      parse_schedule(option, text, ANY);
  } catch (const UsageError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(Schedule, TwoKeysAreTheSmoothstepRampOfASingleTarget) {
  // The single-number target's ramp, V_t(n) = V0 (1 - (1 - R) s(n / ramp)), in closed form.
  const Schedule s({{0, 1.0}, {100, 0.3}});
  for (int n = -5; n <= 130; ++n)
    EXPECT_NEAR(s.at(n), target_volume_at(n, 100, 1.0, 0.3), 1e-15) << n;
}

TEST(Schedule, KeysAreHitExactlyAndHeldOutside) {
  const Schedule s({{10, 0.9}, {60, 0.5}, {120, 0.85}});
  EXPECT_EQ(s.at(10), 0.9);
  EXPECT_EQ(s.at(60), 0.5);
  EXPECT_EQ(s.at(120), 0.85);
  EXPECT_EQ(s.at(0), 0.9);
  EXPECT_EQ(s.at(-3), 0.9);
  EXPECT_EQ(s.at(500), 0.85);
  // Two equal keys hold the value exactly (the "held for 10 frames" of a keyframed target).
  const Schedule held({{0, 1.0}, {60, 0.5}, {70, 0.5}, {130, 1.0}});
  for (int n = 60; n <= 70; ++n) EXPECT_EQ(held.at(n), 0.5) << n;
}

TEST(Schedule, MonotoneBetweenKeysWithoutOvershootOnRandomKeys) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> gap(1, 40);
  std::uniform_real_distribution<double> value(-2.0, 2.0);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<Keyframe> keys;
    int f = gap(rng) - 1;
    for (int k = 0; k < 2 + trial % 6; ++k, f += gap(rng)) keys.push_back({f, value(rng)});
    const Schedule s(keys);
    for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
      const double lo = std::min(keys[i].value, keys[i + 1].value);
      const double hi = std::max(keys[i].value, keys[i + 1].value);
      const double dir = keys[i + 1].value >= keys[i].value ? 1.0 : -1.0;
      double previous = s.at(keys[i].frame);
      for (int q = 1; q <= 64; ++q) {
        const double t = keys[i].frame + (keys[i + 1].frame - keys[i].frame) * q / 64.0;
        const double v = s.at(t);
        ASSERT_GE(v, lo) << "trial " << trial << " segment " << i;
        ASSERT_LE(v, hi) << "trial " << trial << " segment " << i;
        ASSERT_GE(dir * (v - previous), -1e-15) << "not monotone: trial " << trial;
        previous = v;
      }
    }
  }
}

TEST(Schedule, SlopeIsContinuousAtInteriorKeysAndZeroWhereTheCurveTurns) {
  // Finite differences on both sides of each key: a C1 curve has the same one-sided slopes (to
  // O(h)); the turn at frame 60 (down, then up) and the ends have slope 0.
  const Schedule s({{0, 1.0}, {30, 0.8}, {60, 0.5}, {120, 0.85}, {150, 0.9}});
  const double h = 1e-4;
  for (int key : {30, 60, 120}) {
    const double left = (s.at(key) - s.at(key - h)) / h;
    const double right = (s.at(key + h) - s.at(key)) / h;
    EXPECT_NEAR(left, right, 1e-5) << key;
  }
  EXPECT_NEAR((s.at(60 + h) - s.at(60)) / h, 0.0, 1e-5);
  EXPECT_NEAR((s.at(h) - s.at(0)) / h, 0.0, 1e-5);
  EXPECT_NEAR((s.at(150) - s.at(150 - h)) / h, 0.0, 1e-5);
  // Through a key on a monotone run (1 -> 0.8 -> 0.5) the curve does not stop: the slope at 30
  // lies strictly between 0 and 3 times the smaller secant's (Fritsch-Carlson).
  const double slope = (s.at(30 + h) - s.at(30 - h)) / (2 * h);
  EXPECT_LT(slope, 0.0);
  EXPECT_GT(slope, 3.0 * std::max(-0.2 / 30, -0.3 / 30));
}

TEST(Schedule, ParsesTheIssueExampleAndReadsBackItsText) {
  const Schedule s = parse_volume_schedule("target-volume", " 0:1, 60 : 0.5,120:0.85 ", RATIO);
  ASSERT_EQ(s.keys().size(), 3u);
  EXPECT_EQ(s.keys()[1].frame, 60);
  EXPECT_EQ(s.keys()[1].value, 0.5);
  EXPECT_EQ(s.text(), "0:1, 60:0.5, 120:0.85");
  EXPECT_EQ(parse_volume_schedule("target-volume", s.text(), RATIO), s);
  // A first key after frame 0 eases from the rest volume.
  const Schedule later = parse_volume_schedule("target-volume", "60:0.5", RATIO);
  EXPECT_EQ(later.text(), "0:1, 60:0.5");
  // Re-inflation past the rest volume is allowed up to MAX_KEYED_VOLUME_RATIO.
  EXPECT_EQ(parse_volume_schedule("target-volume", "0:1, 50:0.4, 90:1.2", RATIO).last_value(), 1.2);
}

TEST(Schedule, BadKeysAreRefusedNamingTheKey) {
  const auto expect = [](const std::string& option, const std::string& text,
                         const std::vector<std::string>& parts) {
    const std::string m = usage_message(option, text);
    for (const std::string& p : parts)
      EXPECT_NE(m.find(p), std::string::npos) << "'" << text << "' -> " << m;
  };
  expect("target-volume", "0:1, 60:0.5, 50:0.8", {"`target_volume`", "key 3", "'50:0.8'", "increase"});
  expect("target-volume", "0:1, 60:0.5, 60:0.8", {"key 3", "'60:0.8'"});
  expect("target-volume", "0:1, 60:2.5", {"key 2", "'60:2.5'", "(0, 2]"});
  expect("target-volume", "0:1, 60:0", {"key 2", "(0, 2]"});
  expect("target-volume", "0:1, 60:-0.5", {"key 2"});
  expect("target-volume", "0:1, abc", {"key 2", "FRAME:VALUE"});
  expect("target-volume", "0:1, 6x:0.5", {"key 2", "'6x'"});
  expect("target-volume", "0:1, 60:0.5x", {"key 2", "'0.5x'"});
  expect("target-volume", "0:1, 60:nan", {"key 2", "'nan'"});
  expect("target-volume", "0:1,, 60:0.5", {"key 2", "empty"});
  expect("target-volume", "0:1, 60:0.5,", {"key 3", "empty"});
  expect("target-volume", "-5:1", {"key 1", "'-5'"});
  expect("target-volume", "0:0.5, 60:0.4", {"key 1", "rest volume"});
  expect("target-volume", "1.5:0.5", {"key 1", "'1.5'"});
  expect("pressure", "0:4, 10:x", {"`pressure`", "key 2", "'x'"});
  // A frame past the largest int names the limit (it said "not an integer >= 0").
  expect("pressure", "0:4, 2147483648:1", {"key 2", "'2147483648'", "[0, 2147483647]"});
}

TEST(Schedule, OptionTableTakesANumberOrKeys) {
  RunOptions r;
  set_run_option(r, "target-volume", "0:1, 60:0.5, 120:0.85");
  EXPECT_EQ(r.sim.target_volume, 0.85);  // what "has a target" and the end's check read
  EXPECT_EQ(r.sim.target_volume_schedule.keys().size(), 3u);
  EXPECT_EQ(find_run_option("target-volume")->get(r), "0:1, 60:0.5, 120:0.85");
  set_run_option(r, "target-volume", "0.3");  // a single number again: today's meaning
  EXPECT_TRUE(r.sim.target_volume_schedule.empty());
  EXPECT_EQ(r.sim.target_volume, 0.3);
  EXPECT_EQ(find_run_option("target-volume")->get(r), "0.3");
  EXPECT_THROW(set_run_option(r, "target-volume", "1"), UsageError);  // [0, 1) as before

  set_run_option(r, "pressure", "0:4, 100:-2, 150:1");
  EXPECT_EQ(r.sim.pressure, 4.0);  // the largest key: "is there a compressing pressure"
  EXPECT_EQ(find_run_option("pressure")->get(r), "0:4, 100:-2, 150:1");
  set_run_option(r, "pressure", "2");
  EXPECT_TRUE(r.sim.pressure_schedule.empty());
  EXPECT_EQ(r.sim.pressure, 2.0);

  RunOptions keyed;
  set_run_option(keyed, "target-volume", "0:1, 60:0.5");
  resolve_run_options(keyed);
  keyed.given.insert("target_ramp");
  const std::vector<std::string> w = ineffective_options(keyed);
  EXPECT_TRUE(std::any_of(w.begin(), w.end(), [](const std::string& s) {
    return s.find("`target_ramp` has no effect") != std::string::npos;
  }));
}

TEST(Schedule, ARampLongerThanHalfTheFramesIsNamedWithTheKeysThatTimeIt) {
  // `--target-ramp 72 -n 72` was halved without a word, so a deflation meant to last the whole
  // animation ended half way through it (review "tasks" F1).
  RunOptions o;
  o.sim.frames = 72;
  o.sim.target_volume = 0.4;
  o.sim.target_ramp_frames = 72;
  o.given.insert("target_ramp");
  const std::vector<std::string> w = ineffective_options(o);
  EXPECT_EQ(std::count_if(w.begin(), w.end(),
                          [](const std::string& s) {
                            return s.rfind(
                                       "`target_ramp` 72 is more than half of `frames` (72): "
                                       "the run shortens it to 36",
                                       0) == 0 &&
                                   s.find("(`target_volume` \"0:1, 72:0.4\")") != std::string::npos;
                          }),
            1)
      << (w.empty() ? "" : w.front());
  // Within half the frames, or not given (the default ramp, shortened as documented): nothing.
  o.sim.target_ramp_frames = 36;
  for (const std::string& s : ineffective_options(o))
    EXPECT_EQ(s.find("more than half of `frames`"), std::string::npos) << s;
  o.sim.target_ramp_frames = 100;
  o.given.clear();
  for (const std::string& s : ineffective_options(o))
    EXPECT_EQ(s.find("more than half of `frames`"), std::string::npos) << s;
}

double cgal_volume(const Mesh& mesh, const Positions& x) {
  Mesh m = mesh;
  for (VertexIndex v : m.vertices()) m.point(v) = Point3(x(v.idx(), 0), x(v.idx(), 1), x(v.idx(), 2));
  return CGAL::Polygon_mesh_processing::volume(m);
}

/// The volume of each frame's positions by CGAL on a copy of the input mesh, in input units: a
/// measure independent of the simulator's own V/V0 (signed_volume, normalization).
struct CgalVolumes final : RunObserver {
  const Mesh* mesh = nullptr;
  double v0 = 0.0;
  std::vector<double> ratios{1.0};  // frame 0 = the rest state
  std::vector<long> contacts{0};
  void frame(const FrameView& view, const FrameMetrics& m) override {
    ratios.push_back(cgal_volume(*mesh, view.positions()) / v0);
    contacts.push_back(m.collision.contacts);
  }
};

TEST(Schedule, VolumeDeflatesAndReinflatesToItsKeys) {
  // The issue's case on a small mesh: deflate to 0.25 (deep enough that the folds touch), hold
  // 10 frames, re-inflate to the rest volume, hold 10 frames. V/V0, measured by CGAL, within
  // 0.005 of each key over its hold, and no new self-intersection once the contacts of the
  // deflated shell have let go. With the option reading one number only, the run could not come
  // back up (the keys are refused as a number).
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/ico3.off");
  RunOptions o;
  set_run_option(o, "target-volume", "0:1, 80:0.25, 90:0.25, 170:1, 180:1");
  set_run_option(o, "frames", "180");
  set_run_option(o, "validate", "end");
  CgalVolumes rec;
  rec.mesh = &mesh;
  rec.v0 = CGAL::Polygon_mesh_processing::volume(mesh);
  const RunResult r = run_contraction(mesh, o, &rec);
  ASSERT_EQ(r.frames_run, 180) << r.message;
  EXPECT_EQ(r.status, RunStatus::Completed) << r.message;
  EXPECT_EQ(r.new_intersections, 0);
  EXPECT_TRUE(r.target_reached);
  for (int n = 80; n <= 90; ++n) EXPECT_NEAR(rec.ratios[n], 0.25, 0.005) << "frame " << n;
  for (int n = 170; n <= 180; ++n) EXPECT_NEAR(rec.ratios[n], 1.0, 0.005) << "frame " << n;
  // Between keys the shell follows the curve, too (the constraint projects every step).
  for (int n : {40, 130}) {
    const Schedule& s = o.sim.target_volume_schedule;
    EXPECT_NEAR(rec.ratios[n], s.at(n), 0.005) << "frame " << n;
  }
  // The folds touched while deflated, and let go on the way up.
  EXPECT_GT(*std::max_element(rec.contacts.begin() + 70, rec.contacts.begin() + 91), 0);
  EXPECT_EQ(*std::max_element(rec.contacts.begin() + 170, rec.contacts.end()), 0);
}

TEST(Schedule, ConstantPressureKeysRunBitForBitAsTheNumber) {
  // pressure_at returns the keys' value exactly where they hold it, so a flat schedule and the
  // single number give the same bits: the keyed path adds nothing of its own to the step.
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/ico2.off");
  RunOptions a, b;
  for (RunOptions* o : {&a, &b}) set_run_option(*o, "frames", "30");
  set_run_option(a, "pressure", "4");
  set_run_option(b, "pressure", "0:4, 10:4, 1000:4");
  const RunResult ra = run_contraction(mesh, a, nullptr);
  const RunResult rb = run_contraction(mesh, b, nullptr);
  ASSERT_EQ(ra.positions.rows(), rb.positions.rows());
  EXPECT_TRUE((ra.positions.array() == rb.positions.array()).all());
}

TEST(Schedule, PressureFollowsItsKeys) {
  // Compress for 60 frames, then pull outward (-p < 0): the shell shrinks and then grows again;
  // with a single -p 4 it keeps shrinking.
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/ico2.off");
  RunOptions keyed, single;
  for (RunOptions* o : {&keyed, &single}) {
    set_run_option(*o, "frames", "160");
    set_run_option(*o, "air-balance", "0");
  }
  set_run_option(keyed, "pressure", "0:4, 60:4, 80:-4");
  set_run_option(single, "pressure", "4");
  CgalVolumes k, s;
  k.mesh = s.mesh = &mesh;
  k.v0 = s.v0 = CGAL::Polygon_mesh_processing::volume(mesh);
  run_contraction(mesh, keyed, &k);
  run_contraction(mesh, single, &s);
  ASSERT_EQ(k.ratios.size(), 161u);
  EXPECT_NEAR(k.ratios[60], s.ratios[60], 1e-12);  // the same run up to frame 60
  EXPECT_LT(k.ratios[60], 0.99);
  EXPECT_GT(k.ratios[160], k.ratios[80] + 0.01);   // grows again under the negative pressure
  EXPECT_LT(s.ratios[160], s.ratios[80]);          // the single number keeps shrinking
}

}  // namespace
}  // namespace shellcontract
