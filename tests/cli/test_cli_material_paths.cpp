// An OBJ written to another folder than its input (run -o, --export-dir frames, repair -o) names
// the same material libraries as its input: each mtllib path resolves, from the output's folder,
// to the input's .mtl file itself (never a copy); a library that does not exist is kept as written
// with a warning naming the input file and line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_runner.hpp"
#include "support/textured_obj.hpp"

namespace {

using shellcontract::test::run_cli;
namespace fs = std::filesystem;

class CliMaterialPaths : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " has not been built yet";
    dir_ = fs::temp_directory_path() / ("shellcontract_mtllib_" + std::to_string(::getpid()));
    fs::create_directories(dir_ / "in" / "mats");
    fs::create_directories(dir_ / "out" / "deeper");
    // Two libraries on one line (the spec), one of them in a subfolder, one with a space in its
    // name (Blender writes such names as they are).
    std::string text = shellcontract::test::textured_uv_sphere().text;
    text.replace(text.find("mtllib sphere.mtl"), 17, "mtllib sphere.mtl mats/my extra.mtl");
    write(dir_ / "in" / "a.obj", text);
    write(dir_ / "in" / "sphere.mtl", "newmtl north\nKd 1 0 0\nnewmtl south\nKd 0 0 1\n");
    write(dir_ / "in" / "mats" / "my extra.mtl", "newmtl unused\nKd 0 1 0\n");
  }
  void TearDown() override { fs::remove_all(dir_); }
  static void write(const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; }
  static std::string read(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
  }
  /// The rest of each mtllib line of the file.
  static std::vector<std::string> mtllib_lines(const fs::path& p) {
    std::vector<std::string> out;
    std::istringstream in(read(p));
    for (std::string l; std::getline(in, l);)
      if (l.rfind("mtllib ", 0) == 0) out.push_back(l.substr(7));
    return out;
  }
  /// The input's two libraries resolve from the output's folder to the input's own files.
  void expect_resolves(const fs::path& out) {
    const std::vector<std::string> lines = mtllib_lines(out);
    ASSERT_EQ(lines.size(), 1u);
    const std::string& l = lines[0];
    const std::size_t split = l.find(".mtl ") + 4;  // the first name ends in ".mtl"
    ASSERT_NE(split, std::string::npos + 4) << l;
    const fs::path first = out.parent_path() / l.substr(0, split);
    const fs::path second = out.parent_path() / l.substr(split + 1);
    EXPECT_TRUE(fs::exists(first) && fs::equivalent(first, dir_ / "in" / "sphere.mtl")) << l;
    EXPECT_TRUE(fs::exists(second) && fs::equivalent(second, dir_ / "in" / "mats" / "my extra.mtl")) << l;
    EXPECT_EQ(read(dir_ / "in" / "sphere.mtl"), "newmtl north\nKd 1 0 0\nnewmtl south\nKd 0 0 1\n");
    EXPECT_FALSE(fs::exists(out.parent_path() / "sphere.mtl"));  // referred to, not copied
  }
  fs::path dir_;
};

const std::vector<std::string> RUN = {"--frames", "4", "--target-volume", "0.9", "-q"};

TEST_F(CliMaterialPaths, RunOutputInAnotherFolderNamesTheInputsLibraries) {
  const fs::path out = dir_ / "out" / "deeper" / "b.obj";
  std::vector<std::string> args = {"run", (dir_ / "in" / "a.obj").string(), "-o", out.string()};
  args.insert(args.end(), RUN.begin(), RUN.end());
  const auto r = run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_resolves(out);
}

TEST_F(CliMaterialPaths, ExportedFramesNameTheInputsLibraries) {
  const fs::path out = dir_ / "out" / "b.obj";
  std::vector<std::string> args = {"run", (dir_ / "in" / "a.obj").string(), "-o", out.string(),
                                   "--export-every", "2", "--export-dir", (dir_ / "out" / "deeper").string()};
  args.insert(args.end(), RUN.begin(), RUN.end());
  const auto r = run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_resolves(out);
  int frames = 0;
  for (const auto& e : fs::directory_iterator(dir_ / "out" / "deeper")) {
    expect_resolves(e.path());
    ++frames;
  }
  EXPECT_GE(frames, 2);
}

TEST_F(CliMaterialPaths, RepairCopyInAnotherFolderNamesTheInputsLibraries) {
  const fs::path out = dir_ / "out" / "deeper" / "b.obj";
  const auto r = run_cli({"repair", (dir_ / "in" / "a.obj").string(), "-o", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_resolves(out);
}

TEST_F(CliMaterialPaths, TheSameFolderKeepsTheLineAsWritten) {
  const fs::path out = dir_ / "in" / "b.obj";
  const auto r = run_cli({"repair", (dir_ / "in" / "a.obj").string(), "-o", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read(out), read(dir_ / "in" / "a.obj"));
}

TEST_F(CliMaterialPaths, AMissingLibraryIsKeptWithAWarningNamingFileAndLine) {
  fs::remove(dir_ / "in" / "sphere.mtl");
  const fs::path out = dir_ / "out" / "b.obj";
  std::vector<std::string> args = {"run", (dir_ / "in" / "a.obj").string(), "-o", out.string()};
  args.insert(args.end(), RUN.begin(), RUN.end());
  const auto r = run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: " + (dir_ / "in" / "a.obj").string() + ": line 2: material library 'sphere.mtl' not found"),
            std::string::npos) << r.output;
  const std::vector<std::string> lines = mtllib_lines(out);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0], "sphere.mtl ../in/mats/my extra.mtl");
}

}  // namespace
