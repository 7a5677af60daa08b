// `--version` names the build and the kernels (shellcontract/version.hpp, docs/cli.md), and a
// checkpoint written with one kernel class is refused by the other. Before, every build of one
// release printed "shellcontract 0.2.0", and a checkpoint of an AVX2 machine resumed on a CPU
// without AVX2 (or a build of another commit) continued into a result that was neither run's.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "support/cli_runner.hpp"
#include "support/scratch_dir.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

using test::quoted;
using test::run_command;

/// The CLI with `args` under SHELLCONTRACT_KERNELS=`kernels` ("" leaves it unset).
test::RunResult run_with_kernels(const std::string& kernels, const std::vector<std::string>& args) {
  const std::string env = kernels.empty() ? "env -u SHELLCONTRACT_KERNELS "
                                          : "env SHELLCONTRACT_KERNELS=" + quoted(kernels) + " ";
  return run_command(env + test::cli_command(args));
}

std::string read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class CliVersion : public test::ScratchDirTest {
 protected:
  CliVersion() : ScratchDirTest("shellcontract_version_") {}
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  /// "avx2" or "scalar": what --version says of this machine without the variable.
  std::string native_kernels() {
    const test::RunResult r = run_with_kernels("", {"--version"});
    std::smatch m;
    return std::regex_search(r.output, m, std::regex("\\((avx2|scalar) kernels\\)")) ? m[1].str()
                                                                                     : "";
  }
  const std::string mesh_ = std::string(test::MESH_DIR) + "/bumpy_sphere.off";
};

TEST_F(CliVersion, NamesTheBuildAndTheKernels) {
  const test::RunResult r = run_with_kernels("", {"--version"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  // The release, the commit with a hash of uncommitted changes where built from git, a hash of
  // the toolchain (compiler, version, build type, flags: two such builds of one commit may round
  // differently), the target of a -march=native build (SHELLCONTRACT_NATIVE), the kernels.
  const std::regex form(
      "shellcontract [0-9]+\\.[0-9]+\\.[0-9]+\\+(g[0-9a-f]{12}(\\.dirty\\.[0-9a-f]{8})?\\.)?"
      "tc\\.[0-9a-f]{8}(\\.native(\\.[0-9a-f]{8})?)? \\((avx2|scalar) kernels\\)\n");
  EXPECT_TRUE(std::regex_match(r.output, form)) << r.output;
#ifdef SHELLCONTRACT_TEST_NATIVE_BUILD
  EXPECT_NE(r.output.find("native"), std::string::npos) << r.output;
#else
  EXPECT_EQ(r.output.find("native"), std::string::npos) << r.output;
#endif
  const test::RunResult scalar = run_with_kernels("scalar", {"--version"});
  EXPECT_EQ(scalar.exit_code, 0) << scalar.output;
  EXPECT_NE(scalar.output.find("(scalar kernels)"), std::string::npos) << scalar.output;
  const test::RunResult automatic = run_with_kernels("auto", {"--version"});
  EXPECT_EQ(automatic.output, r.output);
}

TEST_F(CliVersion, AMistypedKernelsVariableIsRefused) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--version"}, std::vector<std::string>{"check", mesh_}}) {
    const test::RunResult r = run_with_kernels("scaler", args);
    EXPECT_EQ(r.exit_code, 1) << args[0] << ": " << r.output;
    EXPECT_NE(r.output.find("SHELLCONTRACT_KERNELS"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("'scaler'"), std::string::npos) << r.output;
  }
}

TEST_F(CliVersion, ScalarKernelsAreDeterministicAndAreTheOnesThatRun) {
  if (native_kernels() != "avx2") GTEST_SKIP() << "this CPU runs the scalar kernels anyway";
  const std::vector<std::string> run{"run", mesh_, "-n", "20", "-q"};
  auto with_output = [&](std::string out) {
    std::vector<std::string> a = run;
    a.insert(a.end(), {"-o", path(out)});
    return a;
  };
  ASSERT_EQ(run_with_kernels("scalar", with_output("s1.off")).exit_code, 0);
  ASSERT_EQ(run_with_kernels("scalar", with_output("s2.off")).exit_code, 0);
  ASSERT_EQ(run_with_kernels("", with_output("v.off")).exit_code, 0);
  EXPECT_EQ(read_bytes(path("s1.off")), read_bytes(path("s2.off")));
  // The two classes round differently (FMA in the batched kernels), which is why checkpoints
  // name them: were these equal, the variable would not have reached the kernels.
  EXPECT_NE(read_bytes(path("s1.off")), read_bytes(path("v.off")));
}

TEST_F(CliVersion, ACheckpointOfOtherKernelsIsRefused) {
  if (native_kernels() != "avx2") GTEST_SKIP() << "this CPU runs the scalar kernels only";
  const std::string ckpt = path("c.ckpt");
  const test::RunResult saved =
      run_with_kernels("", {"run", mesh_, "-n", "6", "--checkpoint", ckpt, "--checkpoint-every",
                            "3", "-o", path("a.off"), "-q"});
  ASSERT_EQ(saved.exit_code, 0) << saved.output;
  ASSERT_TRUE(std::filesystem::exists(ckpt)) << saved.output;
  const test::RunResult other =
      run_with_kernels("scalar", {"run", "--resume", ckpt, "-o", path("b.off"), "-q"});
  EXPECT_EQ(other.exit_code, 2) << other.output;
  EXPECT_NE(other.output.find("(avx2 kernels), this is "), std::string::npos) << other.output;
  EXPECT_NE(other.output.find("(scalar kernels)"), std::string::npos) << other.output;
  EXPECT_FALSE(std::filesystem::exists(path("b.off")));
  // The same kernels resume it (the refusal above is the kernels', not the file's).
  const test::RunResult same =
      run_with_kernels("", {"run", "--resume", ckpt, "-o", path("c.off"), "-q"});
  EXPECT_EQ(same.exit_code, 0) << same.output;
}

}  // namespace
}  // namespace shellcontract
