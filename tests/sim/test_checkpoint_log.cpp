// The caller's log and the run's volume history beside the checkpoint (CheckpointLogFile,
// shellcontract/checkpoint.hpp): the first save of a run holds them (the files beside may be what
// the checkpoint in place needs), each later one appends only what is new to FILE.log and
// FILE.history, so the checkpoint's size grows neither with the log nor with the frames run; a
// save whose append fails (a full disk, a file size limit) leaves the checkpoint in place and its
// files beside consistent, and the saves after it recover.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "shellcontract/error.hpp"
#include "shellcontract/file_error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "sim/checkpoint.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

std::string read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The format number a checkpoint file was written with (after the magic line).
std::uint32_t format_of(const std::string& path) {
  const std::string bytes = read(path);
  const std::size_t at = std::strlen("SHELLCONTRACT-CHECKPOINT\n");
  std::uint32_t format = 0;
  if (bytes.size() >= at + sizeof format) std::memcpy(&format, bytes.data() + at, sizeof format);
  return format;
}

/// What one save left.
struct Save {
  int frame = 0;
  std::uintmax_t checkpoint_bytes = 0;
  double varying = 0;  ///< the bytes of the checkpoint's fields whose size varies (varying_bytes)
  std::size_t history = 0;
  std::vector<double> saved_history;  ///< the checkpoint's, read back after the save
  std::string log;        ///< the caller's log at the save
  std::string saved_log;  ///< the checkpoint's, read back after the save
  std::string error;      ///< the save's UsageError, if it failed
  std::string read_error;  ///< why the checkpoint in place could not be read back, if not
};

/// The bytes of the fields of `c` whose size changes from frame to frame as they are saved: the
/// contacts (4 + 8 + 16 + 32 + 24 + 8 bytes each), the contact correction and skin, the held
/// vertices, the dimples and the run's message. Not the log, nor the volume history (8 bytes a
/// frame so far), which are beside it.
double varying_bytes(const Checkpoint& c) {
  const SimulatorState& s = c.sim;
  return 92.0 * s.collision.contact_cache.size() + 24.0 * s.collision.correction.rows() +
         8.0 * s.collision.skin.size() + static_cast<double>(s.held_by_contact.size()) +
         4.0 * s.dimple_sizes.size() + static_cast<double>(c.progress.message.size());
}

/// Saves every frame to `path` with a log of one 300-byte line a frame kept beside it; calls
/// `before(frame)` ahead of each save. With `resumed`, continues that checkpoint's run and log;
/// with `last` > 0, stops after the save of that frame.
class LoggingCheckpointer final : public RunCheckpointer {
 public:
  LoggingCheckpointer(std::string path, const Mesh& mesh, const RunOptions& options,
                      std::function<void(int)> before = {}, const Checkpoint* resumed = nullptr,
                      int last = 0)
      : path_(std::move(path)),
        hash_(mesh_hash(mesh)),
        options_(options),
        log_(resumed ? resumed->log : "frame,line\n"),
        file_(path_, log_, resumed),
        before_(std::move(before)),
        resumed_(resumed),
        last_(last) {}
  const Checkpoint* resume_from() const override { return resumed_; }
  bool stop() override { return last_ > 0 && frame_ >= last_; }
  bool save_due(int frame) override {
    log_ += std::to_string(frame) + "," + std::string(300, 'x') + "\n";
    frame_ = frame;
    return true;
  }
  void save(const SavedRun& run) override {
    if (before_) before_(frame_);
    Save s;
    s.frame = frame_;
    s.log = log_;
    try {
      write_checkpoint(path_, run, options_, CheckpointInfo{"mesh.off", hash_, {}, {}, 1}, file_);
    } catch (const UsageError& e) {
      s.error = e.what();
    }
    Checkpoint c;
    try {
      c = read_checkpoint(path_);        // after every save, failed or not: whole
    } catch (const std::exception& e) {  // only where a test took a file beside away
      s.read_error = e.what();
      saves.push_back(s);
      return;
    }
    s.checkpoint_bytes = fs::file_size(path_);
    s.history = c.progress.history.size();
    s.saved_history = c.progress.history;
    s.varying = varying_bytes(c);
    s.saved_log = c.log;
    if (s.error.empty()) {
      EXPECT_EQ(c.log, log_) << "frame " << frame_;
    }
    saves.push_back(s);
  }
  std::vector<Save> saves;

 private:
  std::string path_;
  std::uint64_t hash_;
  RunOptions options_;
  std::string log_;
  CheckpointLogFile file_;
  std::function<void(int)> before_;
  const Checkpoint* resumed_;
  int last_;
  int frame_ = 0;
};

class CheckpointLog : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("shellcontract_checkpoint_log_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    mesh_ = read_input_mesh(std::string(test::MESH_DIR) + "/ico1.off");
    set_run_option(options_, "frames", "40");
    resolve_run_options(options_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
  Mesh mesh_;
  RunOptions options_;
};

TEST_F(CheckpointLog, ASaveWritesTheNewLinesBesideAndTheCheckpointDoesNotGrowWithTheRun) {
  const std::string path = file("c.ckpt");
  LoggingCheckpointer saver(path, mesh_, options_, [&](int frame) {
    // The first save holds the log: the file beside is left as it was (another run's), and
    // removed once no checkpoint goes with it.
    if (frame == 1) std::ofstream(checkpoint_log_path(path)) << "another run's\n";
    if (frame == 2) {
      EXPECT_FALSE(fs::exists(checkpoint_log_path(path)));
    }
  });
  run_contraction(mesh_, options_, nullptr, &saver);
  ASSERT_EQ(saver.saves.size(), 39u);
  EXPECT_EQ(format_of(path), 5u);
  for (const Save& s : saver.saves) {
    EXPECT_EQ(s.error, "") << "frame " << s.frame;
  }
  // From the second save on, the checkpoint changes size only with its varying fields: the
  // frame's 300-byte line and its V/V0 are not in it.
  for (std::size_t k = 2; k < saver.saves.size(); ++k) {
    const Save &a = saver.saves[k - 1], &b = saver.saves[k];
    const double grown = static_cast<double>(b.checkpoint_bytes) - a.checkpoint_bytes;
    EXPECT_EQ(grown, b.varying - a.varying) << "frame " << b.frame;
  }
  EXPECT_EQ(read(checkpoint_log_path(path)), saver.saves.back().log);
}

// The volume history (V/V0 after each frame so far), which every save used to hold whole (8 bytes
// a frame, so a save's cost grew with the run): from the second save on it is in FILE.history,
// each save appending the frames since the last, and it reads back whole, frame 0 on.
TEST_F(CheckpointLog, TheVolumeHistoryIsAppendedBesideAndReadsBackWhole) {
  const std::string path = file("c.ckpt");
  const std::string history_path = checkpoint_history_path(path);
  std::vector<std::uintmax_t> beside_sizes;
  LoggingCheckpointer saver(path, mesh_, options_, [&](int frame) {
    // The first save holds the history: another run's file is left as it was, then removed.
    if (frame == 1) std::ofstream(history_path) << "another run's\n";
    if (frame == 2) {
      EXPECT_FALSE(fs::exists(history_path));
    }
    if (frame > 2) beside_sizes.push_back(fs::file_size(history_path));
  });
  run_contraction(mesh_, options_, nullptr, &saver);
  ASSERT_EQ(saver.saves.size(), 39u);
  EXPECT_EQ(format_of(path), 5u);
  // After the save of frame f (from the second one on), the file holds f + 1 values.
  for (std::size_t k = 0; k < beside_sizes.size(); ++k)
    EXPECT_EQ(beside_sizes[k], 8u * (k + 3)) << "after the save of frame " << k + 2;
  for (const Save& s : saver.saves) {
    EXPECT_EQ(s.saved_history.size(), static_cast<std::size_t>(s.frame) + 1) << "frame " << s.frame;
    EXPECT_EQ(s.saved_history.front(), 1.0);
  }
  // Each save's history goes on from the one before, bit for bit (only appended to).
  for (std::size_t k = 1; k < saver.saves.size(); ++k) {
    const std::vector<double>& a = saver.saves[k - 1].saved_history;
    const std::vector<double>& b = saver.saves[k].saved_history;
    ASSERT_GT(b.size(), a.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), 8 * a.size()), 0) << "frame " << saver.saves[k].frame;
  }
  const std::vector<double>& last = saver.saves.back().saved_history;
  ASSERT_EQ(last.size(), 40u);
  const std::string bytes = read(history_path);
  ASSERT_EQ(bytes.size(), 8u * last.size());
  EXPECT_EQ(std::memcmp(bytes.data(), last.data(), bytes.size()), 0);
}

// The formats written before the history went beside still read: 3 (log and history inside)
// and 4 (the log beside, the history inside), with the same log and history as format 5's.
TEST_F(CheckpointLog, CheckpointsOfFormats3And4StillRead) {
  const std::string path = file("c.ckpt");
  LoggingCheckpointer saver(path, mesh_, options_);
  run_contraction(mesh_, options_, nullptr, &saver);
  const Checkpoint c = read_checkpoint(path);
  ASSERT_TRUE(c.history_beside);
  const std::string three = file("three.ckpt"), four = file("four.ckpt");
  write_checkpoint(three, c);
  const LogBeside log{c.log.size(), fnv1a(c.log.data(), c.log.size())};
  write_checkpoint(four, c, &log);
  std::ofstream(checkpoint_log_path(four), std::ios::binary) << c.log;
  EXPECT_EQ(format_of(three), 3u);
  EXPECT_EQ(format_of(four), 4u);
  for (const std::string& p : {three, four}) {
    const Checkpoint r = read_checkpoint(p);
    EXPECT_FALSE(r.history_beside) << p;
    EXPECT_EQ(r.log_beside, p == four) << p;
    EXPECT_EQ(r.log, c.log) << p;
    EXPECT_EQ(r.progress.history, c.progress.history) << p;
    EXPECT_EQ(r.sim.frame, c.sim.frame) << p;
  }
}

// A file size limit (ulimit -f, as a full disk) cuts the append of frame 20's line short: that
// save fails, the checkpoint of frame 19 and the longer log beside it still read as frame 19's;
// the next save holds its log (format 3), and the one after puts it beside again.
TEST_F(CheckpointLog, AFailedAppendLeavesAPairThatReadsAndTheNextSavesRecover) {
  const std::string path = file("c.ckpt");
  std::signal(SIGXFSZ, SIG_IGN);
  rlimit before{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &before), 0);
  std::vector<std::uint32_t> formats;
  LoggingCheckpointer saver(path, mesh_, options_, [&](int frame) {
    if (frame > 1) formats.push_back(format_of(path));
    rlimit limit = before;
    if (frame == 20) limit.rlim_cur = fs::file_size(checkpoint_log_path(path)) + 10;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limit), 0);
  });
  run_contraction(mesh_, options_, nullptr, &saver);
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &before), 0);
  std::signal(SIGXFSZ, SIG_DFL);
  ASSERT_EQ(saver.saves.size(), 39u);
  const Save& failed = saver.saves[19];
  ASSERT_EQ(failed.frame, 20);
  EXPECT_NE(failed.error.find(checkpoint_log_path(path)), std::string::npos) << failed.error;
  // Read back after the failure (in save()): the checkpoint of frame 19, with its log.
  EXPECT_EQ(failed.history, saver.saves[18].history);
  EXPECT_EQ(failed.saved_log, saver.saves[18].log);
  EXPECT_GT(fs::file_size(checkpoint_log_path(path)), 0u);
  for (std::size_t k = 0; k < saver.saves.size(); ++k)
    if (k != 19) {
      EXPECT_EQ(saver.saves[k].error, "") << "frame " << saver.saves[k].frame;
    }
  // formats[k]: the format in place after the save of frame k + 1.
  ASSERT_EQ(formats.size(), 38u);
  EXPECT_EQ(formats[0], 3u);   // frame 1's save: its log inside
  EXPECT_EQ(formats[1], 5u);   // frame 2's: beside
  EXPECT_EQ(formats[19], 5u);  // frame 20's failed: frame 19's left in place
  EXPECT_EQ(formats[20], 3u);  // frame 21's: its log inside again
  EXPECT_EQ(formats[21], 5u);  // frame 22's: beside
  EXPECT_EQ(format_of(path), 5u);
  EXPECT_EQ(read_checkpoint(path).log, saver.saves.back().log);
}

// The log beside removed while the run saves to it (by hand, or by a tool cleaning the folder):
// the save says the file was removed, not that its folder is missing (before: "cannot write
// 'c.ckpt.log': the folder does not exist"), and the next saves recover as after any failure.
TEST_F(CheckpointLog, ALogRemovedBetweenSavesIsNamedAsRemovedAndTheNextSavesRecover) {
  const std::string path = file("c.ckpt");
  LoggingCheckpointer saver(path, mesh_, options_, [&](int frame) {
    if (frame == 20) fs::remove(checkpoint_log_path(path));
  });
  run_contraction(mesh_, options_, nullptr, &saver);
  ASSERT_EQ(saver.saves.size(), 39u);
  const Save& failed = saver.saves[19];
  ASSERT_EQ(failed.frame, 20);
  EXPECT_NE(failed.error.find(checkpoint_log_path(path) + "': it was removed since the last save"),
            std::string::npos)
      << failed.error;
  EXPECT_EQ(failed.error.find("folder"), std::string::npos) << failed.error;
  // The checkpoint in place (frame 19's) needed that log: it cannot be read until a save holds
  // the log again, which the next one does.
  EXPECT_NE(failed.read_error, "");
  for (std::size_t k = 20; k < saver.saves.size(); ++k) {
    EXPECT_EQ(saver.saves[k].error, "") << "frame " << saver.saves[k].frame;
    EXPECT_EQ(saver.saves[k].read_error, "") << "frame " << saver.saves[k].frame;
  }
  EXPECT_EQ(read_checkpoint(path).log, saver.saves.back().log);
}

// A hard link to a checkpoint under another name is the same file, but its files beside are
// not: `--resume A --checkpoint B` with B a hard link of A, and B.log and B.history another
// run's. The first save into B holds its log and history itself (format 3), as for any other
// file; before, it took B's files beside for A's and appended to them, and the checkpoint it
// wrote was refused ("its log ... is not the one the checkpoint was saved with"). Resuming A
// into A itself still appends to A's files beside (format 5 from the first save).
TEST_F(CheckpointLog, AHardLinkOfTheResumedCheckpointIsAnotherFileWithItsOwnFilesBeside) {
  const std::string a = file("a.ckpt"), b = file("b.ckpt");
  LoggingCheckpointer first(a, mesh_, options_, {}, nullptr, 10);
  run_contraction(mesh_, options_, nullptr, &first);
  LoggingCheckpointer other(b, mesh_, options_, {}, nullptr, 5);
  run_contraction(mesh_, options_, nullptr, &other);
  ASSERT_EQ(format_of(a), 5u);
  ASSERT_EQ(format_of(b), 5u);
  fs::remove(b);
  fs::create_hard_link(a, b);
  const Checkpoint resumed = read_checkpoint(a);
  ASSERT_EQ(resumed.sim.frame, 10);
  ASSERT_TRUE(resumed.log_beside && resumed.history_beside);

  LoggingCheckpointer into_link(b, mesh_, options_, {}, &resumed, 12);
  run_contraction(mesh_, options_, nullptr, &into_link);
  ASSERT_EQ(into_link.saves.size(), 2u);
  EXPECT_EQ(into_link.saves[0].frame, 11);
  for (const Save& s : into_link.saves) {
    EXPECT_EQ(s.error, "") << "frame " << s.frame;
    EXPECT_EQ(s.read_error, "") << "frame " << s.frame;
    EXPECT_EQ(s.saved_log, s.log) << "frame " << s.frame;
    EXPECT_EQ(s.history, static_cast<std::size_t>(s.frame) + 1) << "frame " << s.frame;
  }
  const Checkpoint saved = read_checkpoint(b);
  EXPECT_EQ(saved.sim.frame, 12);
  EXPECT_EQ(saved.log, into_link.saves.back().log);
  // A, the file resumed from, is left as it was, with its own files beside.
  const Checkpoint again = read_checkpoint(a);
  EXPECT_EQ(again.sim.frame, 10);
  EXPECT_EQ(again.log, resumed.log);

  LoggingCheckpointer into_itself(a, mesh_, options_, {}, &resumed, 11);
  run_contraction(mesh_, options_, nullptr, &into_itself);
  ASSERT_EQ(into_itself.saves.size(), 1u);
  EXPECT_EQ(into_itself.saves[0].error, "");
  EXPECT_EQ(into_itself.saves[0].read_error, "");
  EXPECT_EQ(format_of(a), 5u);
  EXPECT_EQ(read_checkpoint(a).log, into_itself.saves[0].log);
}

// The same with the checkpoint named without a folder (in the current one): its path has no
// folder part, which the check of the folder must take as "." (before: the folder message).
TEST_F(CheckpointLog, ALogRemovedBetweenSavesIsNamedAsRemovedInTheCurrentFolderToo) {
  const fs::path before = fs::current_path();
  fs::current_path(dir_);
  LoggingCheckpointer saver("c.ckpt", mesh_, options_, [&](int frame) {
    if (frame == 20) fs::remove(checkpoint_log_path("c.ckpt"));
  });
  run_contraction(mesh_, options_, nullptr, &saver);
  fs::current_path(before);
  ASSERT_EQ(saver.saves.size(), 39u);
  EXPECT_NE(saver.saves[19].error.find("'c.ckpt.log': it was removed since the last save"),
            std::string::npos)
      << saver.saves[19].error;
}

/// What `read` threw with no descriptor left to open a file (the soft limit of open files
/// lowered to the lowest free descriptor, then restored): "InputFileError EMFILE: what()", or
/// the kind of anything else it threw or returned.
template <class Read>
std::string without_descriptors(Read read) {
  rlimit old{};
  if (::getrlimit(RLIMIT_NOFILE, &old) != 0) return "getrlimit failed";
  const int lowest = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  if (lowest < 0) return "no descriptor to start with";
  ::close(lowest);
  rlimit low = old;
  low.rlim_cur = static_cast<rlim_t>(lowest);
  if (::setrlimit(RLIMIT_NOFILE, &low) != 0) return "setrlimit failed";
  std::string what = "nothing thrown";
  try {
    read();
  } catch (const InputFileError& e) {
    what = std::string("InputFileError ") + (e.error_number() == EMFILE ? "EMFILE" : "other") +
           ": " + e.what();
  } catch (const std::exception& e) {
    what = std::string("another exception: ") + e.what();
  }
  ::setrlimit(RLIMIT_NOFILE, &old);
  return what;
}

// A checkpoint, or its log or history beside, that the process has no descriptor to open is a
// checkpoint not read: an InputFileError (exit code 2, "cannot open file"), which a sweep keeps
// for the job's next attempt. Before: the reader's ResourceFileError, exit code 3, which a sweep
// took for the job's final failure, and it removed the checkpoint.
TEST_F(CheckpointLog, ACheckpointOrAFileBesideWithoutADescriptorToOpenItIsNotRead) {
  const std::string path = file("c.ckpt");
  std::ofstream(path) << "SHELLCONTRACT-CHECKPOINT\n";
  std::ofstream(checkpoint_log_path(path)) << "frame\n";
  std::ofstream(checkpoint_history_path(path)) << "01234567";
  const std::string limit = ": cannot open file: Too many open files";
  const std::string checkpoint = without_descriptors([&] { read_checkpoint(path); });
  EXPECT_EQ(checkpoint.rfind("InputFileError EMFILE: checkpoint " + path + limit, 0), 0u)
      << checkpoint;
  const std::string log = without_descriptors([&] { read_log_beside(path, LogBeside{6, 0}); });
  EXPECT_EQ(log.rfind("InputFileError EMFILE: checkpoint " + path + ": its log " +
                          checkpoint_log_path(path) + limit,
                      0),
            0u)
      << log;
  const std::string history = without_descriptors([&] {
    read_history_beside(path, LogBeside{1, 0});
  });
  EXPECT_EQ(history.rfind("InputFileError EMFILE: checkpoint " + path + ": its volume history " +
                              checkpoint_history_path(path) + limit,
                          0),
            0u)
      << history;
}

}  // namespace
}  // namespace shellcontract
