// The formats the CLI names, in its messages and help texts, against the format table
// (src/mesh/formats.hpp): a format added to the table and not to a text, or to a text and not to
// the table, fails here. The library's messages are compared in tests/mesh/test_formats.cpp.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>

#include "mesh/formats.hpp"
#include "support/cli_runner.hpp"
#include "support/format_lists.hpp"
#include "support/gltf_files.hpp"
#include "support/scratch_dir.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::Extensions;
using test::listed;
using test::rows;
using test::run_cli;
using test::RunResult;

bool plain_or_gltf(const MeshFormat& f) { return f.plain_writer || f.gltf; }

std::string mesh_path(const std::string& name) { return std::string(test::MESH_DIR) + "/" + name; }

class CliFormats : public test::ScratchDirTest {
 protected:
  CliFormats() : ScratchDirTest("shellcontract_cli_formats_") {}
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH))
      GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " has not been built yet";
    ScratchDirTest::SetUp();
  }
  std::string out(const std::string& name) const { return (dir_ / name).string(); }
};

TEST_F(CliFormats, HelpTextsNameTheTablesFormats) {
  const RunResult check = run_cli({"check", "--help"});
  ASSERT_EQ(check.exit_code, 0) << check.output;
  EXPECT_EQ(listed(check.output, "Reads MESH ("), rows(any_format));
  // run: the plain formats for any input; then the glTF ones, for an input of that format.
  const RunResult run = run_cli({"run", "--help"});
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::size_t at = run.output.find("output mesh (format from the extension:");
  ASSERT_NE(at, std::string::npos) << run.output;
  const std::string o = run.output.substr(at, run.output.find(')', at) - at);
  EXPECT_EQ(listed(o.substr(0, o.find(';')), "extension:"), rows(&MeshFormat::plain_writer)) << o;
  EXPECT_EQ(listed(o.substr(o.find(';')), ";"), rows(&MeshFormat::gltf)) << o;
  const RunResult repair = run_cli({"repair", "--help"});
  ASSERT_EQ(repair.exit_code, 0) << repair.output;
  EXPECT_EQ(listed(repair.output, "format from the extension:"), rows(plain_or_gltf));
}

TEST_F(CliFormats, RefusedNamesListTheTablesFormats) {
  const std::string in = mesh_path("cube.off");
  const RunResult run = run_cli({"run", in, "-o", out("r.xyz"), "--frames", "2", "-q"});
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_EQ(listed(run.output, "expected "), rows(plain_or_gltf));
  EXPECT_EQ(listed(run.output, ", or "), rows(&MeshFormat::gltf));
  const RunResult repair = run_cli({"repair", in, "-o", out("r.xyz")});
  EXPECT_EQ(repair.exit_code, 1) << repair.output;
  EXPECT_EQ(listed(repair.output, "expected "), rows(plain_or_gltf));
  const std::string unknown = write("m.xyz", "OFF\n");
  const RunResult check = run_cli({"check", unknown});
  EXPECT_EQ(check.exit_code, 2) << check.output;
  EXPECT_EQ(listed(check.output, "expected "), rows(any_format));
}

// A .glb result of an input whose document cannot be written (--repair changed the mesh) names
// the formats that can be written instead.
TEST_F(CliFormats, AGltfResultThatCannotBeWrittenNamesThePlainFormats) {
  test::GltfScene scene;
  scene.primitives.push_back(test::octahedron_primitive(false, false));
  scene.primitives[0].indices.resize(21);  // one face less: open, so --repair fills it
  const std::string in = write("open.glb", test::glb_bytes(test::gltf_parts(scene)));
  const RunResult r = run_cli({"run", in, "-o", out("r.glb"), "--repair", "--frames", "2", "-q"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(listed(r.output, "choose an ", " output"), rows(&MeshFormat::plain_writer)) << r.output;
  EXPECT_FALSE(fs::exists(out("r.glb")));
}

// `repair` read a file of no known extension as an STL: it "repaired" an STL named .dat, which
// `check` and `run` refuse, and called any other file one with no faces. It refuses it now for
// its extension, as they do, and writes nothing.
TEST_F(CliFormats, RepairRefusesAnInputOfNoKnownExtension) {
  const RunResult stl = run_cli({"repair", mesh_path("cube.off"), "-o", out("cube.stl")});
  ASSERT_EQ(stl.exit_code, 0) << stl.output;
  fs::copy_file(out("cube.stl"), out("cube.dat"));
  const RunResult r = run_cli({"repair", out("cube.dat"), "-o", out("r.off")});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("unknown extension: '.dat'"), std::string::npos) << r.output;
  EXPECT_EQ(listed(r.output, "expected "), rows(any_format));
  EXPECT_FALSE(fs::exists(out("r.off")));
  // As check says it, the file named once (it read "F: cannot repair: the file cannot be read
  // (F: unknown extension ...)").
  const std::string name = out("cube.dat");
  EXPECT_EQ(r.output.find(name), r.output.rfind(name)) << r.output;
}

}  // namespace
}  // namespace shellcontract
