// The run's log beside its checkpoint (FILE.log, shellcontract/checkpoint.hpp CheckpointLogFile):
// a save writes the log's new lines there, not the whole log into the checkpoint. Before, every
// save held the CSV of every frame so far, so a checkpoint grew by a log line a frame and a long
// run spent the square of its frames on saving. A process ended between the append and the
// checkpoint's rename leaves a log longer than recorded, which a resume cuts; a log missing, cut
// or damaged is refused (exit 2) naming it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "sim/checkpoint.hpp"
#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::run_cli;

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

/// The CSV log without its timing columns (step_ms, solve_ms, ccd_ms: the 8th to 10th), which
/// differ from run to run.
std::string without_times(const std::string& csv) {
  std::istringstream in(csv);
  std::string line, out;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    int c = 0;
    for (std::string cell; std::getline(row, cell, ','); ++c)
      if (c < 7 || c > 9) out += cell + ",";
    out += "\n";
  }
  return out;
}

/// The bytes of the fields of `c` whose size changes from frame to frame as they are saved: the
/// contacts (4 + 8 + 16 + 32 + 24 + 8 bytes each), the contact correction and skin, the held
/// vertices, the dimples, the run's message and the options' text (`--frames 41` or `401`). Not
/// the log, nor the volume history (8 bytes a frame so far): they are beside it.
double varying_bytes(const Checkpoint& c) {
  const SimulatorState& s = c.sim;
  double options = 0;
  for (const OptionValues* o : {&c.given, &c.resolved})
    for (const auto& [name, value] : *o) options += static_cast<double>(name.size() + value.size());
  return 92.0 * s.collision.contact_cache.size() + 24.0 * s.collision.correction.rows() +
         8.0 * s.collision.skin.size() + static_cast<double>(s.held_by_contact.size()) +
         4.0 * s.dimple_sizes.size() + static_cast<double>(c.progress.message.size()) + options;
}

/// The first `n` lines of `text`.
std::string first_lines(const std::string& text, std::size_t n) {
  std::size_t end = 0;
  for (; n > 0 && end != std::string::npos; --n) {
    end = text.find('\n', end);
    if (end != std::string::npos) ++end;
  }
  return text.substr(0, end);
}

class CliCheckpointLog : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
    dir_ = fs::temp_directory_path() /
           ("shellcontract_cli_checkpoint_log_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string out(const std::string& name) const { return (dir_ / name).string(); }
  static std::string mesh(const std::string& name) {
    return std::string(test::MESH_DIR) + "/" + name;
  }
  /// Runs ico2 for `frames` frames (deep enough for contacts), saving every `every` frames to
  /// NAME.ckpt, with its mesh and log in NAME.off and NAME.csv.
  void run(const std::string& name, int frames, int every) {
    const auto r = run_cli({"run", mesh("ico2.off"), "-o", out(name + ".off"), "--log",
                            out(name + ".csv"), "-q", "--target-volume", "0.3", "--target-ramp",
                            "30", "--frames", std::to_string(frames), "--checkpoint",
                            out(name + ".ckpt"), "--checkpoint-every", std::to_string(every)});
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  /// Resumes NAME.ckpt into NAME-resumed.off and .csv; returns the CLI's exit code and output.
  test::RunResult resume(const std::string& name, const std::vector<std::string>& more = {}) {
    std::vector<std::string> args{"run",
                                  "--resume",
                                  out(name + ".ckpt"),
                                  "-o",
                                  out(name + "-resumed.off"),
                                  "--log",
                                  out(name + "-resumed.csv"),
                                  "-q"};
    args.insert(args.end(), more.begin(), more.end());
    return run_cli(args);
  }
  fs::path dir_;
};

// A checkpoint's size does not grow with the run's length beyond the contacts of the frame it is
// at: the log's lines are in FILE.log and the volume history (V/V0 after each frame, 8 bytes a
// frame, which every save used to hold whole) in FILE.history, once.
TEST_F(CliCheckpointLog, ACheckpointDoesNotGrowWithTheFramesSoFar) {
  run("short", 41, 10);
  run("long", 401, 10);
  const Checkpoint a = read_checkpoint(out("short.ckpt")), b = read_checkpoint(out("long.ckpt"));
  ASSERT_EQ(a.sim.frame, 40);
  ASSERT_EQ(b.sim.frame, 400);
  const double grown = static_cast<double>(fs::file_size(out("long.ckpt"))) -
                       static_cast<double>(fs::file_size(out("short.ckpt")));
  EXPECT_EQ(grown, varying_bytes(b) - varying_bytes(a))
      << "the log of 360 more frames is " << b.log.size() - a.log.size() << " bytes, their V/V0 "
      << 8 * (b.progress.history.size() - a.progress.history.size());
  // The history beside it: V/V0 after each frame up to the checkpoint's, 401 values.
  ASSERT_EQ(b.progress.history.size(), 401u);
  const std::string history = read(checkpoint_history_path(out("long.ckpt")));
  ASSERT_EQ(history.size(), 8u * 401);
  EXPECT_EQ(std::memcmp(history.data(), b.progress.history.data(), history.size()), 0);
  // The log beside it is the run's log up to the checkpoint's frame: the header and 400 rows.
  const std::string beside = read(checkpoint_log_path(out("long.ckpt")));
  EXPECT_EQ(b.log, beside);
  const std::string whole = read(out("long.csv"));
  EXPECT_EQ(whole.compare(0, beside.size(), beside), 0);
  EXPECT_EQ(std::count(beside.begin(), beside.end(), '\n'), 401);
}

// A save that ended between its append to FILE.log and the rename of its checkpoint: the log is
// longer than the checkpoint in place records. The resume takes only the recorded part, goes on
// saving to FILE (cutting the log back before it appends), and ends as the run never stopped.
TEST_F(CliCheckpointLog, ALogLongerThanRecordedResumesAsTheWholeRun) {
  run("whole", 80, 1000);  // no save: the run to compare with
  run("cut", 80, 25);      // its last save at frame 75
  const std::string log_path = checkpoint_log_path(out("cut.ckpt"));
  const std::string recorded = read(log_path);
  ASSERT_EQ(read_checkpoint(out("cut.ckpt")).sim.frame, 75);
  // What the next save would have appended, and a part line, as a process killed mid-append.
  const std::string later = read(out("cut.csv")).substr(recorded.size());
  write(log_path, recorded + later + "77,0.5,");
  const auto r = resume("cut", {"--checkpoint-every", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read(out("cut-resumed.off")), read(out("whole.off"))) << "the meshes differ";
  EXPECT_EQ(without_times(read(out("cut-resumed.csv"))), without_times(read(out("whole.csv"))));
  // The resumed run saved into cut.ckpt (frames 76 and 78) and its log: no trace of the surplus.
  const Checkpoint saved = read_checkpoint(out("cut.ckpt"));
  EXPECT_EQ(saved.sim.frame, 78);
  EXPECT_EQ(saved.log, read(log_path));
  EXPECT_EQ(without_times(saved.log), first_lines(without_times(read(out("whole.csv"))), 79));
}

// Without its log, or with one cut short or changed, a checkpoint is refused as bad input (exit 2),
// naming the checkpoint and the log, and nothing is written.
TEST_F(CliCheckpointLog, AMissingCutOrDamagedLogIsRefusedNamingIt) {
  run("run", 30, 10);
  const std::string log_path = checkpoint_log_path(out("run.ckpt"));
  const std::string log = read(log_path);
  const auto refused = [&](const std::string& what, const std::string& why) {
    SCOPED_TRACE(what);
    const auto r = resume("run");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("checkpoint " + out("run.ckpt") + ": its log"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find(log_path), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(why), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out("run-resumed.off")));
    EXPECT_FALSE(fs::exists(out("run-resumed.csv")));
  };
  fs::remove(log_path);
  refused("missing", "no such file");
  write(log_path, log.substr(0, log.size() - 1));
  refused("cut", "fewer than the");
  std::string damaged = log;
  damaged[damaged.size() / 2] ^= 1;
  write(log_path, damaged);
  refused("damaged", "is not the one the checkpoint was saved with");
  write(log_path, log);
  const auto r = resume("run");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// Review 7 (F6): only the part of FILE.log and FILE.history that the checkpoint records is read.
// Both were read whole, then cut to that part: a log made 1 GB larger cost 1 GB, and these
// (8 GB, sparse: no disk) ended in "out of memory", exit 3, under the memory limit here.
TEST_F(CliCheckpointLog, OnlyTheRecordedPartOfTheFilesBesideIsRead) {
  run("run", 30, 10);
  const std::string log_path = checkpoint_log_path(out("run.ckpt"));
  const std::string history_path = checkpoint_history_path(out("run.ckpt"));
  fs::resize_file(log_path, std::uintmax_t{8} << 30);
  fs::resize_file(history_path, std::uintmax_t{8} << 30);
  const auto r = test::run_cli_limited(
      3000000, {"run", "--resume", out("run.ckpt"), "-o", out("run-resumed.off"), "-q",
                "--checkpoint", out("other.ckpt")});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out("run-resumed.off")));
}

// As the log: without its volume history, or with one cut short or changed, a checkpoint is
// refused as bad input (exit 2), naming the checkpoint and the file, and nothing is written.
TEST_F(CliCheckpointLog, AMissingCutOrDamagedHistoryIsRefusedNamingIt) {
  run("run", 30, 10);
  const std::string path = checkpoint_history_path(out("run.ckpt"));
  const std::string history = read(path);
  const auto refused = [&](const std::string& what, const std::string& why) {
    SCOPED_TRACE(what);
    const auto r = resume("run");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("checkpoint " + out("run.ckpt") + ": its volume history " + path),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find(why), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out("run-resumed.off")));
    EXPECT_FALSE(fs::exists(out("run-resumed.csv")));
  };
  fs::remove(path);
  refused("missing", "no such file");
  write(path, history.substr(0, history.size() - 1));
  refused("cut", "fewer than the");
  std::string damaged = history;
  damaged[damaged.size() / 2] ^= 1;
  write(path, damaged);
  refused("damaged", "is not the one the checkpoint was saved with");
  // Another output in its place is refused before any work, as for the log.
  const auto r = run_cli({"run", mesh("ico1.off"), "-o", out("a.off"), "-q", "--frames", "5",
                          "--checkpoint", out("c.ckpt"), "--log", out("c.ckpt.history")});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("c.ckpt.history"), std::string::npos) << r.output;
  write(path, history);
  EXPECT_EQ(resume("run").exit_code, 0);
}

// A run's first save cannot know whose FILE.log is there (another run's, which the checkpoint in
// place may need): it holds the log itself (format 3) and leaves the file beside alone; the next
// saves put the log beside. A checkpoint with its log inside, as every one before format 4 was,
// still resumes, and the resumed run goes on saving into it.
TEST_F(CliCheckpointLog, TheFirstSaveHoldsItsLogAndOlderCheckpointsResume) {
  run("whole", 60, 1000);
  run("one", 60, 25);  // saves at 25 and 50
  write(out("other.csv"), "another run's log\n");
  fs::copy_file(out("other.csv"), checkpoint_log_path(out("first.ckpt")));
  run("first", 60, 40);  // one save, at 40
  const Checkpoint first = read_checkpoint(out("first.ckpt"));
  EXPECT_FALSE(first.log_beside);
  EXPECT_EQ(first.log, read(out("first.csv")).substr(0, first.log.size()));
  // No checkpoint goes with the file that was beside it any more: removed.
  EXPECT_FALSE(fs::exists(checkpoint_log_path(out("first.ckpt"))));
  const auto r = resume("first", {"--checkpoint-every", "5"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read(out("first-resumed.off")), read(out("whole.off")));
  EXPECT_EQ(without_times(read(out("first-resumed.csv"))), without_times(read(out("whole.csv"))));
  // Saved at 45 (its log inside: the file beside was not this run's yet), then 50 and 55 beside.
  const Checkpoint later = read_checkpoint(out("first.ckpt"));
  EXPECT_EQ(later.sim.frame, 55);
  EXPECT_TRUE(later.log_beside);
  EXPECT_EQ(later.log, read(checkpoint_log_path(out("first.ckpt"))));
  EXPECT_TRUE(read_checkpoint(out("one.ckpt")).log_beside);
}

// The file beside is an output of the run: --log over it is refused before any work, as two
// outputs in one file are.
TEST_F(CliCheckpointLog, TheLogBesideIsAnOutputOfItsOwn) {
  const auto r = run_cli({"run", mesh("ico1.off"), "-o", out("a.off"), "-q", "--frames", "5",
                          "--checkpoint", out("c.ckpt"), "--log", out("c.ckpt.log")});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("c.ckpt.log"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out("a.off")));
}

}  // namespace
}  // namespace shellcontract
