// Checkpoints (sim/checkpoint.hpp): a run stopped at frame k, saved to a file and continued
// from it takes the same steps, to the bit, as the run that was never stopped, at any thread
// count; and each piece of the saved state is needed (leaving one out changes the result, so the
// equality is not the trivial one of a state that did not matter). Checkpoints of another mesh,
// other options or another version are refused, saying which.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <string>

#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "sim/checkpoint.hpp"
#include "sim/simulator.hpp"
#include "support/memory_checkpointer.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

using test::MemoryCheckpointer;

RunOptions options_from(const std::vector<std::pair<std::string, std::string>>& given) {
  RunOptions o;
  for (const auto& [name, value] : given) set_run_option(o, name, value);
  return o;
}

Mesh read(const std::string& name) {
  return read_input_mesh(std::string(test::MESH_DIR) + "/" + name);
}

std::string temp_file(const std::string& name) {
  return (fs::temp_directory_path() / ("shellcontract_checkpoint_" + name)).string();
}

/// Runs to frame `at`, stops, saves to a file, reads it back (optionally changed by `edit`) and
/// continues with `threads` threads.
RunResult stop_and_resume(const Mesh& mesh, RunOptions options, int at, int threads,
                          const std::function<void(Checkpoint&)>& edit = {},
                          Checkpoint* saved_out = nullptr) {
  MemoryCheckpointer saver(mesh, options, at, /*stop=*/true);
  const RunResult first = run_contraction(mesh, options, nullptr, &saver);
  EXPECT_EQ(first.status, RunStatus::Cancelled);
  EXPECT_EQ(first.frames_run, at);
  EXPECT_TRUE(saver.saved.has_value());
  const std::string path = temp_file(std::to_string(::getpid()) + ".ckpt");
  write_checkpoint(path, *saver.saved);
  Checkpoint c = read_checkpoint(path);
  std::remove(path.c_str());
  if (saved_out) *saved_out = c;
  if (edit) edit(c);
  set_run_option(options, "threads", std::to_string(threads));
  MemoryCheckpointer resumer(&c);
  return run_contraction(mesh, options_for_resume(c, options), nullptr, &resumer);
}

void expect_same_run(const RunResult& a, const RunResult& b) {
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.frames_run, b.frames_run);
  EXPECT_EQ(a.final_volume_ratio, b.final_volume_ratio);
  EXPECT_EQ(a.min_volume_ratio, b.min_volume_ratio);
  EXPECT_EQ(a.frame_target_reached, b.frame_target_reached);
  EXPECT_EQ(a.new_intersections, b.new_intersections);
  ASSERT_EQ(a.positions.rows(), b.positions.rows());
  EXPECT_TRUE((a.positions.array() == b.positions.array()).all()) << "positions differ";
  // The totals' counts (the times differ, of course).
  const auto ta = a.totals.per_step(a.frames_run), tb = b.totals.per_step(b.frames_run);
  ASSERT_EQ(ta.size(), tb.size());
  for (std::size_t i = 0; i < ta.size(); ++i) {
    if (ta[i].first.find("_ms") == std::string::npos && ta[i].first.find("seconds") == std::string::npos) {
      EXPECT_EQ(ta[i].second, tb[i].second) << ta[i].first;
    }
  }
}

struct Case {
  const char* name;
  const char* mesh;
  std::vector<std::pair<std::string, std::string>> options;
  int at;
};

// A target volume deep enough that the shell meets itself (contacts, held vertices, the warm
// start's cache at the checkpoint); the local contraction's dimples; the default run's air.
const Case CASES[] = {
    {"target_with_contacts", "bumpy_sphere.off",
     {{"target-volume", "0.25"}, {"target-ramp", "20"}, {"frames", "50"}, {"validate", "end"}},
     30},
    {"regions_dimples", "bumpy_sphere.off",
     {{"regions", "auto"}, {"pressure", "0"}, {"frames", "40"}, {"target-ramp", "20"}}, 12},
    {"default_air_coloured", "ico2.off", {{"frames", "30"}, {"order", "coloured"}}, 13},
    // The air stops the shell above the stop ratio: the run stalls at frame 172, which the
    // criterion finds by looking 20 frames back, past the checkpoint at 160.
    {"stall_across_the_checkpoint", "ico2.off", {{"stop-volume-ratio", "0.3"}, {"frames", "400"}},
     160},
};

class CheckpointResume : public ::testing::TestWithParam<Case> {};

TEST_P(CheckpointResume, EqualsTheRunNeverStoppedAtAnyThreadCount) {
  const Case& k = GetParam();
  const Mesh mesh = read(k.mesh);
  const RunOptions options = options_from(k.options);
  const RunResult whole = run_contraction(mesh, options);
  ASSERT_GT(whole.frames_run, k.at) << "the run must go on past the checkpoint";
  for (int threads : {1, 2}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    expect_same_run(whole, stop_and_resume(mesh, options, k.at, threads));
  }
}

INSTANTIATE_TEST_SUITE_P(Runs, CheckpointResume, ::testing::ValuesIn(CASES),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(Checkpoint, EveryPieceOfTheStateMatters) {
  // Each edit drops one piece of the saved state; the continued run must then differ from the
  // whole one (else the test above would pass without saving that piece).
  const Case& k = CASES[0];
  const Mesh mesh = read(k.mesh);
  const RunOptions options = options_from(k.options);
  const RunResult whole = run_contraction(mesh, options);
  Checkpoint saved;
  stop_and_resume(mesh, options, k.at, 1, {}, &saved);
  ASSERT_FALSE(saved.sim.collision.contact_cache.empty()) << "no contacts at the checkpoint";
  bool held = false;
  for (char h : saved.sim.held_by_contact) held = held || h;
  ASSERT_TRUE(held) << "no vertex held by a contact at the checkpoint";
  const std::vector<std::pair<const char*, std::function<void(Checkpoint&)>>> edits = {
      {"velocities", [](Checkpoint& c) { c.sim.v.setZero(); }},
      {"contact cache", [](Checkpoint& c) { c.sim.collision.contact_cache.clear(); }},
      {"held vertices", [](Checkpoint& c) { c.sim.held_by_contact.assign(c.sim.held_by_contact.size(), 0); }},
  };
  for (const auto& [what, edit] : edits) {
    const RunResult r = stop_and_resume(mesh, options, k.at, 1, edit);
    const bool same = r.frames_run == whole.frames_run &&
                      (r.positions.array() == whole.positions.array()).all();
    EXPECT_FALSE(same) << "leaving out the " << what << " changed nothing";
  }
  // The volume history decides the stall: without it the run goes on past frame 172.
  const Case& stall = CASES[3];
  const Mesh ico2 = read(stall.mesh);
  const RunOptions stall_options = options_from(stall.options);
  const RunResult stalled = run_contraction(ico2, stall_options);
  ASSERT_EQ(stalled.status, RunStatus::TargetNotReached);
  ASSERT_LT(stalled.frames_run, 180);
  ASSERT_GT(stalled.frames_run, stall.at);
  const RunResult without = stop_and_resume(ico2, stall_options, stall.at, 1, [](Checkpoint& c) {
    c.progress.history.assign(1, 1.0);
  });
  EXPECT_GT(without.frames_run, stalled.frames_run) << "leaving out the volume history changed nothing";
}

TEST(Checkpoint, RefusesOtherOptionsNamingThem) {
  const Mesh mesh = read("ico1.off");
  const RunOptions options = options_from({{"frames", "10"}, {"pressure", "2"}});
  MemoryCheckpointer saver(mesh, options, 4, true);
  run_contraction(mesh, options, nullptr, &saver);
  ASSERT_TRUE(saver.saved.has_value());
  RunOptions other = options_from({{"pressure", "3"}, {"threads", "2"}});
  try {
    options_for_resume(*saver.saved, other);
    FAIL() << "other options accepted";
  } catch (const UsageError& e) {
    // By field, which each front end spells its own way (the CLI's --pressure, Python's pressure).
    EXPECT_NE(std::string(e.what()).find("`pressure` 3"), std::string::npos) << e.what();
    EXPECT_NE(spell_options(e.what(), OptionSpelling::Cli).find("--pressure 3 (the checkpoint's: 2)"), std::string::npos);
    EXPECT_EQ(std::string(e.what()).find("threads"), std::string::npos) << e.what();
  }
  // The same values again, and another thread count, are accepted; nothing given takes the
  // checkpoint's.
  EXPECT_NO_THROW(options_for_resume(*saver.saved, options_from({{"pressure", "2"}, {"threads", "1"}})));
  const RunOptions taken = options_for_resume(*saver.saved, RunOptions{});
  EXPECT_EQ(taken.sim.frames, 10);
  EXPECT_EQ(taken.sim.pressure, 2.0);
}

// Options given that exclude one of the checkpoint's (--regions auto against its --region-at) are
// a mismatch with the checkpoint, named as such: before, the message was the exclusion alone
// ("--region-at excludes --regions"), about an option the command line did not hold.
TEST(Checkpoint, OptionsThatExcludeTheCheckpointsAreNamedAsAMismatch) {
  const Mesh mesh = read("ico1.off");
  const RunOptions options = options_from({{"frames", "6"}, {"pressure", "0"}, {"region-at", "0,0,1"}});
  MemoryCheckpointer saver(mesh, options, 3, true);
  run_contraction(mesh, options, nullptr, &saver);
  ASSERT_TRUE(saver.saved.has_value());
  try {
    options_for_resume(*saver.saved, options_from({{"regions", "auto"}}));
    FAIL() << "options that exclude the checkpoint's accepted";
  } catch (const UsageError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("the checkpoint was written with other options"), std::string::npos) << msg;
    EXPECT_NE(msg.find("--region-at"), std::string::npos) << msg;
  }
}

// run_contraction itself refuses a checkpoint that is not of its mesh and options (run.hpp:
// "InputError if its checkpoint does not fit the mesh and options"). Before, only the state's
// sizes were checked: the checkpoint of ico1 continued on ico1 stretched ended at V/V0 1.4 with
// status ok, and one of another pressure or frame count ran on as if it were this run's.
TEST(Checkpoint, RunContractionRefusesACheckpointOfAnotherMeshOrOtherOptions) {
  const Mesh mesh = read("ico1.off");
  const RunOptions options = options_from({{"frames", "10"}, {"pressure", "2"}});
  MemoryCheckpointer saver(mesh, options, 4, /*stop=*/true);
  run_contraction(mesh, options, nullptr, &saver);
  ASSERT_TRUE(saver.saved.has_value());
  MemoryCheckpointer resumer(&*saver.saved);
  // The same connectivity at other positions: as many vertices, so the state fits its arrays.
  Mesh stretched = mesh;
  for (const VertexIndex v : stretched.vertices()) {
    const Point3 p = stretched.point(v);
    stretched.point(v) = Point3(2.0 * p.x() + 1.0, 0.5 * p.y(), p.z());
  }
  const auto refusal = [&](const Mesh& m, const RunOptions& o) -> std::string {
    try {
      run_contraction(m, o, nullptr, &resumer);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(accepted)";
  };
  EXPECT_NE(refusal(stretched, options).find("another input"), std::string::npos);
  const std::string pressure = refusal(mesh, options_from({{"frames", "10"}, {"pressure", "3"}}));
  EXPECT_NE(pressure.find("`pressure` 3 (the checkpoint's: 2)"), std::string::npos) << pressure;
  const std::string frames = refusal(mesh, options_from({{"frames", "3"}, {"pressure", "2"}}));
  EXPECT_NE(frames.find("`frames` 3"), std::string::npos) << frames;
  // Its own mesh and options, at another thread count, resume to the whole run's bytes.
  const RunResult whole = run_contraction(mesh, options);
  const RunResult resumed = run_contraction(
      mesh, options_from({{"frames", "10"}, {"pressure", "2"}, {"threads", "1"}}), nullptr, &resumer);
  expect_same_run(whole, resumed);
}

TEST(Checkpoint, RefusesAnotherInputOrVersionAndDamagedFiles) {
  const Mesh mesh = read("ico1.off");
  const RunOptions options = options_from({{"frames", "10"}});
  MemoryCheckpointer saver(mesh, options, 4, true);
  run_contraction(mesh, options, nullptr, &saver);
  ASSERT_TRUE(saver.saved.has_value());
  EXPECT_NO_THROW(check_checkpoint_input(*saver.saved, "ico1.off", mesh));
  EXPECT_THROW(check_checkpoint_input(*saver.saved, "ico2.off", read("ico2.off")), InputError);
  Checkpoint old = *saver.saved;
  old.version = "0.0.1";
  try {
    check_checkpoint_input(old, "ico1.off", mesh);
    FAIL() << "another version accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("0.0.1"), std::string::npos) << e.what();
  }
  // A file cut short, or with one byte changed, is refused (never resumed into another state).
  const std::string path = temp_file("damaged.ckpt");
  write_checkpoint(path, *saver.saved);
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  EXPECT_EQ(read_checkpoint(path).sim.x, saver.saved->sim.x);
  for (const std::string& damaged :
       {bytes.substr(0, bytes.size() / 2), bytes.substr(0, bytes.size() - 1),
        bytes.substr(0, 200) + char(bytes[200] ^ 1) + bytes.substr(201)}) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << damaged;
    EXPECT_THROW(read_checkpoint(path), InputError);
  }
  std::remove(path.c_str());
}

}  // namespace
}  // namespace shellcontract
