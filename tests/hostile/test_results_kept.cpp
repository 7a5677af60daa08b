// A finished result is never thrown away: an output that fails (a full disk,
// a small tmpfs here) costs only itself; the others are written and the end names each one.
// And the summary is valid UTF-8 whatever the bytes of the file names.
#include "hostile/hostile_support.hpp"

namespace shellcontract {
namespace {

using test::Hostile;
using test::run_cli;

// Before: the frame export failed on the full disk, all frames ran, then exit 1 with neither
// -o nor --log nor --summary written.
TEST_F(Hostile, AFullDiskStopsTheExportNotTheResult) {
  std::string why;
  if (!mount_tmpfs(dir_ / "small", 64 * 1024, why)) SKIP_OR_FAIL_UNDER_CI(why);
  const auto r = run_cli({"run", test::mesh("bumpy_sphere.off"), "-o", (dir_ / "o.off").string(), "-n", "20", "-q",
                          "--export-every", "1", "--export-dir", (dir_ / "small" / "frames").string(), "--log",
                          (dir_ / "log.csv").string(), "--summary", (dir_ / "s.json").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "o.off")) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "log.csv")) << r.output;
  ASSERT_TRUE(fs::exists(dir_ / "s.json")) << r.output;
  EXPECT_NE(r.output.find("disk is full"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("-o " + (dir_ / "o.off").string() + ": written"), std::string::npos) << r.output;
  EXPECT_NE(test::slurp(dir_ / "s.json").find("\"--export-dir\": \""), std::string::npos);
  // The summary's exit code is the process's (before: 0, with "status": "ok").
  EXPECT_NE(test::slurp(dir_ / "s.json").find("\"exit_code\": 1,"), std::string::npos) << test::slurp(dir_ / "s.json");
  // The result is the one a run without export gives.
  ASSERT_EQ(run_cli({"run", test::mesh("bumpy_sphere.off"), "-o", (dir_ / "ref.off").string(), "-n", "20", "-q"})
                .exit_code,
            0);
  EXPECT_EQ(test::slurp(dir_ / "o.off"), test::slurp(dir_ / "ref.off"));
}

// Before: the summary's "outputs" left out --export-dir and --fields when they were written
// (docs/cli.md: it says which outputs were written).
TEST_F(Hostile, TheSummaryNamesEveryOutputWritten) {
  const auto r = run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "o.off").string(), "-n", "4", "-q",
                          "--export-every", "2", "--export-dir", (dir_ / "frames").string(), "--fields",
                          (dir_ / "f").string(), "--log", (dir_ / "log.csv").string(), "--summary",
                          (dir_ / "s.json").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string summary = test::slurp(dir_ / "s.json");
  // Frames 0, 2 and 4: three files, as many as the folder holds.
  EXPECT_EQ(test::listing(dir_ / "frames").size(), 3u);
  EXPECT_NE(summary.find("\"--export-dir\": \"written (3 frames)\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"--fields\": \"written"), std::string::npos) << summary;
  EXPECT_TRUE(fs::exists(dir_ / "f_start.ply") && fs::exists(dir_ / "f_end.ply"));
  for (const char* option : {"-o", "--log"})
    EXPECT_NE(summary.find("\"" + std::string(option) + "\": \"written\""), std::string::npos) << summary;
}

// --export-failure stop: the user asked that a failed frame file end the run. The run stops
// early (fewer frames than asked), and the result, log and summary of where it stopped are still
// written. Without the option the run would go on to frame 200.
TEST_F(Hostile, AFullDiskEndsTheRunWhenAskedAndKeepsItsResult) {
  std::string why;
  if (!mount_tmpfs(dir_ / "small", 64 * 1024, why)) SKIP_OR_FAIL_UNDER_CI(why);
  const auto r = run_cli({"run", test::mesh("bumpy_sphere.off"), "-o", (dir_ / "o.off").string(), "-n", "200",
                          "-q", "--export-every", "1", "--export-dir", (dir_ / "small" / "frames").string(),
                          "--export-failure", "stop", "--log", (dir_ / "log.csv").string(), "--summary",
                          (dir_ / "s.json").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "o.off")) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "log.csv")) << r.output;
  ASSERT_TRUE(fs::exists(dir_ / "s.json")) << r.output;
  EXPECT_NE(r.output.find("disk is full"), std::string::npos) << r.output;
  const std::string summary = test::slurp(dir_ / "s.json");
  const std::size_t at = summary.find("\"frames_run\": ");
  ASSERT_NE(at, std::string::npos) << summary;
  EXPECT_LT(std::stoi(summary.substr(at + 14)), 200) << "the run did not stop at the failure";
  // Before: "exit_code": 130, the code of Ctrl-C, while the process exited 1.
  EXPECT_NE(summary.find("\"exit_code\": 1,"), std::string::npos) << summary;
  // A value other than warn or stop is refused before any work.
  const auto bad = run_cli({"run", test::mesh("bumpy_sphere.off"), "-o", (dir_ / "b.off").string(),
                            "--export-failure", "maybe"});
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_FALSE(fs::exists(dir_ / "b.off"));
}

// Before: the full disk under the .glb was reported as "serializing the glTF failed", and -o was
// never written.
TEST_F(Hostile, AFullDiskUnderTheGltfIsNamedAndTheResultWritten) {
  std::string why;
  if (!mount_tmpfs(dir_ / "small", 64 * 1024, why)) SKIP_OR_FAIL_UNDER_CI(why);
  test::spit(dir_ / "small" / "a.glb", "an earlier run's");
  const auto r = run_cli({"run", test::mesh("bumpy_sphere.off"), "-o", (dir_ / "o.off").string(), "-n", "20", "-q",
                          "--export-every", "1", "--gltf", (dir_ / "small" / "a.glb").string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "o.off")) << r.output;
  EXPECT_NE(r.output.find("disk is full"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("serializing"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("the old file kept"), std::string::npos) << r.output;
  EXPECT_EQ(test::slurp(dir_ / "small" / "a.glb"), "an earlier run's");
  EXPECT_EQ(test::listing(dir_ / "small"), std::vector<std::string>{"a.glb"}) << "a temporary was left on the full disk";
}

// Before: the summary copied the file name's bytes as they were; a Latin-1 name made it invalid
// UTF-8, so invalid JSON. Checked by Python's strict decoder, independent of our writer.
TEST_F(Hostile, TheSummaryIsValidUtf8ForAnyFileName) {
  const fs::path out = dir_ / std::string("r\xe9sum\xe9.off");
  const fs::path summary = dir_ / "s.json";
  ASSERT_EQ(run_cli({"run", test::mesh("ico2.off"), "-o", out.string(), "-n", "2", "-q", "--summary",
                     summary.string()})
                .exit_code,
            0);
  const auto r = test::run_command("python3 -c \"import json,sys; d=json.loads(open(sys.argv[1],'rb').read()"
                                   ".decode('utf-8')); print(d['output'].encode('latin-1')[-10:])\" " +
                                   test::quoted(summary.string()) + " 2>&1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("r\\xe9sum\\xe9.off"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace shellcontract
