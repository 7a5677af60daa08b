// Outputs are checked by file identity, all of them, before any work: no
// output may be the input, however spelled, nor another output, nor an exported frame's name.
// Each test was run against the code before the fix (cli/output_paths.cpp comparing paths, frame
// 0's name only, `regions` checking nothing) and failed there as its comment says.
#include "hostile/hostile_support.hpp"
#include "shellcontract/options.hpp"

namespace shellcontract {
namespace {

using test::Hostile;
using test::run_cli;

// Before: only frame 0's name was checked, frame 10 replaced the input (exit 0).
TEST_F(Hostile, AnExportedFrameNamedLikeTheInputIsRefused) {
  fs::create_directories(dir_ / "frames");
  const fs::path in = dir_ / "frames" / "ico_10.off";
  fs::copy_file(test::mesh("ico2.off"), in);
  const std::string before = test::slurp(in);
  const auto r = run_cli({"run", in.string(), "-o", (dir_ / "ico.off").string(), "-n", "20", "-q",
                          "--export-every", "10", "--export-dir", (dir_ / "frames").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(test::slurp(in), before) << "the input was overwritten";
  EXPECT_EQ(test::listing(dir_ / "frames"), std::vector<std::string>{"ico_10.off"}) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "ico.off"));
}

// Before: `regions` checked none of its outputs; the face list replaced the input mesh.
TEST_F(Hostile, RegionsFaceListOverTheInputIsRefused) {
  const fs::path in = dir_ / "h.off";
  fs::copy_file(test::mesh("bumpy_sphere.off"), in);
  const std::string before = test::slurp(in);
  const auto r = run_cli({"regions", in.string(), "-o", (dir_ / "r.ply").string(), "--face-list", in.string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(test::slurp(in), before);
  EXPECT_FALSE(fs::exists(dir_ / "r.ply")) << "a refused command writes nothing";
}

// Before: regions hp.ply -o hp.ply replaced its input.
TEST_F(Hostile, RegionsOutputThatIsTheInputIsRefused) {
  const fs::path in = dir_ / "hp.ply";
  ASSERT_EQ(run_cli({"repair", test::mesh("bumpy_sphere.off"), "-o", in.string()}).exit_code, 0);
  const std::string before = test::slurp(in);
  const auto r = run_cli({"regions", in.string(), "-o", in.string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(test::slurp(in), before);
}

// Before: the --region-weights file was no input to the check; --log over it replaced the
// weights (exit 0).
TEST_F(Hostile, AnOutputOverTheWeightsFileIsRefused) {
  const fs::path weights = dir_ / "w.txt";
  std::string text;
  for (int v = 0; v < 162; ++v) text += v < 5 ? "1\n" : "0\n";  // ico2's vertices
  test::spit(weights, text);
  const auto r = run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "o.off").string(), "-n", "2", "-q",
                          "--region-weights", weights.string(), "--log", weights.string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("is the file of --region-weights"), std::string::npos) << r.output;
  EXPECT_EQ(test::slurp(weights), text);
  EXPECT_FALSE(fs::exists(dir_ / "o.off"));
}

// Before: paths were compared, so a hard link to the input passed (exit 0).
// The CLI's list of the files a run reads (cli/run_prepare.cpp, plan.inputs) is kept by hand; the
// option table is walked here, so that a new option whose value is a FILE and that the list leaves
// out (an output over it would replace the user's file) fails this test.
TEST_F(Hostile, AnOutputOverTheFileOfAnyFileOptionIsRefused) {
  int file_options = 0;
  for (const OptionSpec& o : run_option_table()) {
    if (o.value_name.find("FILE") == std::string::npos) continue;
    ++file_options;
    const fs::path file = dir_ / (o.name + ".txt");
    test::spit(file, "0 1 2\n");
    const auto r = run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "o.off").string(), "-n",
                            "2", "-q", "--" + o.name, file.string(), "--log", file.string()});
    EXPECT_EQ(r.exit_code, 1) << "--" << o.name << ": " << r.output;
    EXPECT_NE(r.output.find("is the file of --" + o.name), std::string::npos) << r.output;
    EXPECT_EQ(test::slurp(file), "0 1 2\n") << "--" << o.name << "'s file was overwritten";
    EXPECT_FALSE(fs::exists(dir_ / "o.off"));
  }
  EXPECT_GE(file_options, 2) << "--regions and --region-weights take a FILE";
}

TEST_F(Hostile, AHardLinkToTheInputIsTheInput) {
  const fs::path in = dir_ / "in.off", link = dir_ / "out.off";
  fs::copy_file(test::mesh("ico2.off"), in);
  fs::create_hard_link(in, link);
  const auto r = run_cli({"run", in.string(), "-o", link.string(), "-n", "2", "-q"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("input"), std::string::npos) << r.output;
  EXPECT_EQ(test::slurp(in), test::slurp(test::mesh("ico2.off")));
}

// Before: a bind mount of the input's folder gave another path to the same file; the run
// replaced the input (exit 0).
TEST_F(Hostile, TheInputThroughABindMountIsTheInput) {
  fs::create_directories(dir_ / "a");
  const fs::path in = dir_ / "a" / "in.off";
  fs::copy_file(test::mesh("ico2.off"), in);
  std::string why;
  if (!bind(dir_ / "a", dir_ / "b", why)) SKIP_OR_FAIL_UNDER_CI(why);
  const auto r = run_cli({"run", in.string(), "-o", (dir_ / "b" / "in.off").string(), "-n", "2", "-q"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(test::slurp(in), test::slurp(test::mesh("ico2.off")));
  // The --regions file is an input too.
  fs::copy_file(test::mesh("bumpy_sphere.bumps.txt"), dir_ / "a" / "bumps.txt");
  const auto r2 = run_cli({"run", test::mesh("bumpy_sphere.off"), "-o", (dir_ / "o.off").string(), "-n", "2", "-q",
                           "--regions", (dir_ / "a" / "bumps.txt").string(), "--log",
                           (dir_ / "b" / "bumps.txt").string()});
  EXPECT_EQ(r2.exit_code, 1) << r2.output;
  EXPECT_EQ(test::slurp(dir_ / "a" / "bumps.txt"), test::slurp(test::mesh("bumpy_sphere.bumps.txt")));
}

// Before: a --log named like a frame was silently overwritten by that frame (exit 0).
TEST_F(Hostile, ALogNamedLikeAFrameIsRefused) {
  fs::create_directories(dir_ / "frames");
  const auto r = run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "o.off").string(), "-n", "10", "-q",
                          "--export-every", "5", "--export-dir", (dir_ / "frames").string(), "--log",
                          (dir_ / "frames" / "o_05.off").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(test::listing(dir_ / "frames").empty());
}

// Before: a name too long for the folder was found after the whole run (the progress line of the
// last frame was printed, then exit 1).
TEST_F(Hostile, ANameTooLongIsRefusedBeforeTheRun) {
  const std::string name(300, 'n');
  const auto r = run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / (name + ".off")).string(), "-n", "3"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output.find("frame 3/3"), std::string::npos) << "refused only after the run:\n" << r.output;
  EXPECT_NE(r.output.find("too long"), std::string::npos) << r.output;
}

// Before: create_directories threw a filesystem_error for a too-long --export-dir: exit 3.
TEST_F(Hostile, ATooLongExportFolderIsBadUsage) {
  const auto r = run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "o.off").string(), "-n", "3", "-q",
                          "--export-dir", (dir_ / std::string(300, 'd')).string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "o.off"));
}

// Before: the export folder was created before the outputs were checked.
TEST_F(Hostile, ARefusedRunCreatesNoExportFolder) {
  const auto r = run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "missing" / "o.off").string(), "-n", "3",
                          "-q", "--export-dir", (dir_ / "frames").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "frames"));
  EXPECT_NE(r.output.find("does not exist"), std::string::npos) << r.output;
}

// Before: a run refused after the outputs' check (a bad face list, an unreadable mesh: exit 2)
// left the empty export folder it had made. A folder that was there already stays.
TEST_F(Hostile, ARunRefusedForItsInputLeavesNoExportFolder) {
  test::spit(dir_ / "r.txt", "-1 2 3\n");
  const auto r = run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "o.off").string(), "-n", "3", "-q",
                          "--export-dir", (dir_ / "frames").string(), "--regions", (dir_ / "r.txt").string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(test::listing(dir_), std::vector<std::string>{"r.txt"}) << r.output;
  fs::create_directories(dir_ / "kept");
  const auto again = run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "o.off").string(), "-n", "3", "-q",
                              "--export-dir", (dir_ / "kept").string(), "--regions", (dir_ / "r.txt").string()});
  EXPECT_EQ(again.exit_code, 2) << again.output;
  EXPECT_TRUE(fs::is_directory(dir_ / "kept")) << "a folder the run did not make was removed";
}

// Before: "folder does not exist" when the parent was a file; now it says so.
TEST_F(Hostile, AParentThatIsAFileIsNamed) {
  test::spit(dir_ / "file.txt", "x");
  const auto r = run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "file.txt" / "o.off").string(), "-n", "3"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("is a file"), std::string::npos) << r.output;
}

// Before: a second run into the same --export-dir mixed its frames with the first run's (exit 0).
TEST_F(Hostile, TwoRunsNeverMixTheirFramesInOneFolder) {
  fs::create_directories(dir_ / "a");
  fs::create_directories(dir_ / "b");
  const std::string frames = (dir_ / "frames").string();
  ASSERT_EQ(run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "a" / "o.off").string(), "-n", "4", "-q",
                     "--export-every", "2", "--export-dir", frames})
                .exit_code,
            0);
  const std::vector<std::string> first = test::listing(frames);
  const std::string frame2 = test::slurp(dir_ / "frames" / "o_2.off");
  const auto r = run_cli({"run", test::mesh("bumpy_sphere.off"), "-o", (dir_ / "b" / "o.off").string(), "-n",
                          "4", "-q", "--export-every", "2", "--export-dir", frames});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("another run"), std::string::npos) << r.output;
  EXPECT_EQ(test::listing(frames), first);
  EXPECT_EQ(test::slurp(dir_ / "frames" / "o_2.off"), frame2);
  // Another output name keeps the runs apart in the same folder.
  EXPECT_EQ(run_cli({"run", test::mesh("bumpy_sphere.off"), "-o", (dir_ / "b" / "p.off").string(), "-n", "4",
                     "-q", "--export-every", "2", "--export-dir", frames})
                .exit_code,
            0);
}

}  // namespace
}  // namespace shellcontract
