// A checkpoint records the files its run reads besides the mesh (RunInput: a face list, a weights
// file, or numbers given as arrays) by their contents' hash, and a resumed run whose file has
// changed is refused, naming it. Before: the options compared the file's path only, so a face
// list edited between the checkpoint and --resume was read as it was then and the run went on
// with other regions, to a result that matched neither run. Checkpoints of format 1 (written
// before the inputs were recorded) are still resumed where there is no file to check.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "sim/checkpoint.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

/// Saves the checkpoint at frame `at` to `path`, through the library's own writer, with the
/// inputs as the front ends record them (run_inputs before the run), and stops there.
class FileCheckpointer final : public RunCheckpointer {
 public:
  FileCheckpointer(std::string path, const Mesh& mesh, const RunOptions& options, int at)
      : path_(std::move(path)), hash_(mesh_hash(mesh)), options_(options), inputs_(run_inputs(options)), at_(at) {}
  bool save_due(int frame) override { return frame == at_; }
  void save(const SavedRun& run) override {
    write_checkpoint(path_, run, options_, CheckpointInfo{"mesh.off", hash_, "", inputs_});
    saved_ = true;
  }
  bool stop() override { return saved_; }

 private:
  std::string path_;
  std::uint64_t hash_;
  RunOptions options_;
  std::vector<RunInput> inputs_;
  int at_;
  bool saved_ = false;
};

class CheckpointInputs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("shellcontract_checkpoint_inputs_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    mesh_ = read_input_mesh(std::string(test::MESH_DIR) + "/ico1.off");
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) { return (dir_ / name).string(); }
  static void write(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
  }
  /// Runs `given` to frame 3 and returns the checkpoint read back from its file.
  Checkpoint checkpoint_of(const std::vector<std::pair<std::string, std::string>>& given) {
    RunOptions options;
    for (const auto& [name, value] : given) set_run_option(options, name, value);
    set_run_option(options, "frames", "6");
    set_run_option(options, "pressure", "0");
    resolve_run_options(options);
    FileCheckpointer saver(file("c.ckpt"), mesh_, options, 3);
    EXPECT_EQ(run_contraction(mesh_, options, nullptr, &saver).status, RunStatus::Cancelled);
    return read_checkpoint(file("c.ckpt"));
  }
  /// What a resumed run checks, with `command_line` given: the options, then its files.
  void resume(const Checkpoint& c, const RunOptions& command_line = RunOptions{}) {
    RunOptions options = options_for_resume(c, command_line);
    resolve_run_options(options);
    check_checkpoint_files(c, run_inputs(options));
  }
  static std::string refusal(const std::function<void()>& f) {
    try {
      f();
    } catch (const std::exception& e) {
      return e.what();
    }
    return "(accepted)";
  }
  fs::path dir_;
  Mesh mesh_;
};

TEST_F(CheckpointInputs, EveryOptionOfTheTableThatNamesAFileIsRecordedAsAnInput) {
  // run_inputs names the files a run reads by hand; the table is walked here, so that an option
  // whose value is a FILE and that run_inputs leaves out (a resume would go on after that file
  // changed) fails this test rather than passing unnoticed.
  int file_options = 0;
  for (const OptionSpec& o : run_option_table()) {
    if (o.value_name.find("FILE") == std::string::npos) continue;
    ++file_options;
    const std::string path = file(o.name + ".txt");
    write(path, "0 1 2\n");
    RunOptions options;
    set_run_option(options, o.name, path);
    bool recorded = false;
    for (const RunInput& in : run_inputs(options))
      recorded = recorded || (in.option == option_field(o.name) && in.file == path && !in.arrays);
    EXPECT_TRUE(recorded) << "--" << o.name << " " << o.value_name
                          << " is not among run_inputs (src/sim/checkpoint_inputs.cpp)";
  }
  EXPECT_GE(file_options, 2) << "--regions and --region-weights take a FILE";
}

TEST(CheckpointOptions, TheResultNeutralOptionsAreTableOptionsAndOnlyTheyAreNotCompared) {
  // result_neutral_options() is the one list of options a resumed run may change (and a sweep
  // leaves out of a job's id): each must be a table option by its exact name, and the options a
  // checkpoint compares must be every other one.
  const std::vector<std::string>& neutral = result_neutral_options();
  ASSERT_FALSE(neutral.empty());
  for (const std::string& name : neutral) {
    const OptionSpec* o = find_run_option(name);
    ASSERT_NE(o, nullptr) << "'" << name << "' is no option of the table";
    EXPECT_EQ(o->name, name);
  }
  const OptionValues compared = resolved_options(RunOptions{});
  EXPECT_EQ(compared.size() + neutral.size(), run_option_table().size());
  for (const auto& entry : compared)
    EXPECT_EQ(std::count(neutral.begin(), neutral.end(), entry.first), 0) << entry.first;
}

TEST_F(CheckpointInputs, AFaceListChangedSinceTheCheckpointIsRefusedByName) {
  write(file("reg.txt"), "0 1 2\n");
  const Checkpoint c = checkpoint_of({{"regions", file("reg.txt")}});
  EXPECT_NO_THROW(resume(c));
  write(file("reg.txt"), "3 4 5\n");
  const std::string why = refusal([&] { resume(c); });
  EXPECT_NE(why.find("another input"), std::string::npos) << why;
  EXPECT_NE(why.find("`regions` " + file("reg.txt") + " has changed"), std::string::npos) << why;
  EXPECT_THROW(resume(c), InputError);
  // Back as it was: accepted again. A copy elsewhere is the same input (as a copied mesh is).
  write(file("reg.txt"), "0 1 2\n");
  EXPECT_NO_THROW(resume(c));
  write(file("copy.txt"), "0 1 2\n");
  RunOptions copy;
  set_run_option(copy, "regions", file("copy.txt"));
  EXPECT_NO_THROW(resume(c, copy));
  write(file("other.txt"), "7 8\n");
  RunOptions other;
  set_run_option(other, "regions", file("other.txt"));
  const std::string why_other = refusal([&] { resume(c, other); });
  EXPECT_NE(why_other.find("`regions` " + file("other.txt") + " is not what its run read (`regions` " +
                           file("reg.txt") + ")"),
            std::string::npos)
      << why_other;
}

TEST_F(CheckpointInputs, AWeightsFileChangedSinceTheCheckpointIsRefusedByName) {
  std::string weights;
  for (std::size_t v = 0; v < mesh_.number_of_vertices(); ++v) weights += v < 3 ? "1\n" : "0\n";
  write(file("w.txt"), weights);
  const Checkpoint c = checkpoint_of({{"region-weights", file("w.txt")}});
  EXPECT_NO_THROW(resume(c));
  write(file("w.txt"), "0.5\n" + weights.substr(2));
  const std::string why = refusal([&] { resume(c); });
  EXPECT_NE(why.find("`region_weights` " + file("w.txt") + " has changed"), std::string::npos) << why;
}

TEST_F(CheckpointInputs, WeightsGivenAsNumbersAreComparedAndMustBeGivenAgain) {
  RunOptions options;
  options.vertex_weights.assign(mesh_.number_of_vertices(), 0.0);
  options.vertex_weights[0] = options.vertex_weights[1] = options.vertex_weights[2] = 1.0;
  options.given.insert("region_weights");
  set_run_option(options, "frames", "6");
  resolve_run_options(options);
  FileCheckpointer saver(file("c.ckpt"), mesh_, options, 3);
  run_contraction(mesh_, options, nullptr, &saver);
  const Checkpoint c = read_checkpoint(file("c.ckpt"));
  RunOptions again;
  again.vertex_weights = options.vertex_weights;
  again.given.insert("region_weights");
  EXPECT_NO_THROW(resume(c, again));
  again.vertex_weights[1] = 0.5;
  const std::string why = refusal([&] { resume(c, again); });
  EXPECT_NE(why.find("the `region_weights` given as arrays are not those its run was given"), std::string::npos)
      << why;
  // Not given: the checkpoint has no copy of them (before: "region-weights: expected a file name").
  const std::string missing = refusal([&] { resume(c); });
  EXPECT_NE(missing.find("`region_weights` were given as arrays"), std::string::npos) << missing;
}

// Python writes regions given as arrays to a temporary face-list file: a new path at each call.
TEST_F(CheckpointInputs, RegionsGivenAsArraysAreKnownByContentsNotByTheTemporaryPath) {
  write(file("a.txt"), "0 1 2\n");
  Checkpoint c = checkpoint_of({{"regions", file("a.txt")}});
  for (RunInput& in : c.inputs) in.arrays = true;  // as Python marks them
  write(file("b.txt"), "0 1 2\n");
  RunOptions again;
  set_run_option(again, "regions", file("b.txt"));
  RunOptions resumed = options_for_resume(c, again);
  std::vector<RunInput> now = run_inputs(resumed);
  for (RunInput& in : now) in.arrays = true;
  EXPECT_NO_THROW(check_checkpoint_files(c, now));
  const std::string missing = refusal([&] { options_for_resume(c, RunOptions{}); });
  EXPECT_NE(missing.find("`regions` were given as arrays"), std::string::npos) << missing;
  RunOptions automatic;
  set_run_option(automatic, "regions", "auto");
  const std::string other = refusal([&] { options_for_resume(c, automatic); });
  EXPECT_NE(other.find("`regions` auto (the checkpoint's: given as arrays)"), std::string::npos) << other;
}

/// `bytes` (a checkpoint of the current format whose run read no file) rewritten as format 1: no
/// inputs list after the mesh's hash, no interval between saves after the log (format 3), and
/// the checksum over the rest.
std::string as_format_one(std::string bytes) {
  const std::size_t format_at = std::strlen("SHELLCONTRACT-CHECKPOINT\n");
  std::uint32_t format = 1;
  std::memcpy(&bytes[format_at], &format, sizeof format);
  std::size_t at = format_at + sizeof format;
  for (int text = 0; text < 2; ++text) {  // version, input
    std::uint64_t n = 0;
    std::memcpy(&n, &bytes[at], sizeof n);
    at += sizeof n + n;
  }
  at += sizeof(std::uint64_t);  // the mesh's hash
  std::uint64_t inputs = 0;
  std::memcpy(&inputs, &bytes[at], sizeof inputs);
  EXPECT_EQ(inputs, 0u);
  bytes.erase(at, sizeof inputs);
  bytes.resize(bytes.size() - 2 * sizeof(std::uint64_t));  // the checksum, the interval
  const std::uint64_t sum = fnv1a(bytes.data(), bytes.size());
  bytes.append(reinterpret_cast<const char*>(&sum), sizeof sum);
  return bytes;
}

TEST_F(CheckpointInputs, FormatOneCheckpointsResumeWhereThereIsNoFileToCheck) {
  const Checkpoint c = checkpoint_of({{"target-volume", "0.9"}});
  std::ifstream in(file("c.ckpt"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  write(file("old.ckpt"), as_format_one(bytes));
  const Checkpoint old = read_checkpoint(file("old.ckpt"));
  EXPECT_FALSE(old.inputs_recorded);
  EXPECT_EQ(old.save_every, 0);  // not recorded: a resumed run saves only on a signal
  EXPECT_EQ(old.sim.x, c.sim.x);
  EXPECT_NO_THROW(resume(old));
  // With a face list the checkpoint cannot vouch for: refused, saying why.
  Checkpoint with_file = old;
  write(file("reg.txt"), "0 1 2\n");
  with_file.given.emplace_back("regions", file("reg.txt"));
  for (auto& [name, value] : with_file.resolved)
    if (name == "regions") value = file("reg.txt");
  const std::string why = refusal([&] { resume(with_file); });
  EXPECT_NE(why.find("written before checkpoints recorded the files"), std::string::npos) << why;
  EXPECT_NE(why.find(file("reg.txt")), std::string::npos) << why;
}

// Format 3: the saving run's interval between saves, which a run resumed without one takes.
TEST_F(CheckpointInputs, TheIntervalBetweenSavesIsRecorded) {
  Checkpoint c = checkpoint_of({});
  EXPECT_EQ(c.save_every, 0);
  c.save_every = 7;
  write_checkpoint(file("every.ckpt"), c);
  EXPECT_EQ(read_checkpoint(file("every.ckpt")).save_every, 7);
  c.save_every = -1;
  write_checkpoint(file("negative.ckpt"), c);
  const std::string why = refusal([&] { read_checkpoint(file("negative.ckpt")); });
  EXPECT_NE(why.find("a negative interval between saves"), std::string::npos) << why;
}

// Before: "basic_filebuf::underflow error reading the file: Is a directory" (std::ios_base::failure,
// exit 3 in the CLI, RuntimeError in Python).
TEST_F(CheckpointInputs, AFolderGivenAsTheCheckpointIsNamedAsAFolder) {
  const std::string why = refusal([&] { read_checkpoint(dir_.string()); });
  EXPECT_NE(why.find("checkpoint " + dir_.string() + ": cannot open file: it is a folder"), std::string::npos) << why;
  EXPECT_THROW(read_checkpoint(dir_.string()), InputError);
}

}  // namespace
}  // namespace shellcontract
