// No output may be a file that the input mesh reads or names (docs/design/output-safety.md,
// "Files the input needs"): an OBJ's material library and the images it names, a PLY's
// TextureFile, a glTF's external buffer and images. Each command is refused (exit 1) before any
// work, naming the output and the input, and the file is left as it was. Before the check knew
// these files, every command here ended with exit 0 and the file replaced (a .gltf whose buffer
// became a JSON summary could no longer be read).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_runner.hpp"
#include "support/gltf_files.hpp"
#include "support/scratch_dir.hpp"
#include "support/textured_obj.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

class CliInputDependencies : public test::ScratchDirTest {
 protected:
  CliInputDependencies() : ScratchDirTest("shellcontract_cli_deps_") {}
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH))
      GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " has not been built yet";
    ScratchDirTest::SetUp();
  }
  /// The CLI run in the scratch folder, with paths relative to it (as the user types them).
  test::RunResult run_here(const std::vector<std::string>& args) const {
    return test::run_command("cd " + test::quoted(dir_.string()) + " && " +
                             test::cli_command(args));
  }
  std::string read(const std::string& name) const {
    std::ifstream f(dir_ / name, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
  }
  /// The names in the scratch folder, sorted.
  std::vector<std::string> listing() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_))
      names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
  /// A refused command: exit 1, a message with every piece of `said`, `kept` unchanged, and no
  /// other file than `before` in the folder.
  void expect_refused(const test::RunResult& r, const std::vector<std::string>& said,
                      const std::string& kept, const std::string& kept_bytes,
                      const std::vector<std::string>& before) const {
    EXPECT_EQ(r.exit_code, 1) << r.output;
    for (const std::string& s : said)
      EXPECT_NE(r.output.find(s), std::string::npos) << s << "\n" << r.output;
    EXPECT_EQ(read(kept), kept_bytes) << kept << " was written over";
    EXPECT_EQ(listing(), before) << "a refused command creates nothing";
  }
  /// A .gltf (octahedron) whose buffer is the external file `bin`.
  void write_gltf(const std::string& name, const std::string& bin, const std::string& extra = "") {
    test::GltfScene s;
    s.primitives.push_back(test::octahedron_primitive(false, true));
    s.extra = extra;
    const test::GltfParts parts = test::gltf_parts(s);
    write(name, test::gltf_text(parts, bin));
    write(bin, parts.bin);
  }
  /// The textured sphere as an OBJ whose library is c.mtl, and the library naming two images.
  void write_obj() {
    write("c.obj", test::textured_uv_sphere().text);  // "mtllib sphere.mtl"
    std::string obj = read("c.obj");
    obj.replace(obj.find("mtllib sphere.mtl"), 17, "mtllib c.mtl");
    write("c.obj", obj);
    write("c.mtl",
          "newmtl north\nKd 1 0 0\nmap_Kd tex.png\nnewmtl south\nbump -bm 0.5 normal map.png\n");
    write("tex.png", "\x89PNG\r\n\x1a\nnot really");
    write("normal map.png", "\x89PNG\r\n\x1a\nnot either");
  }
};

TEST_F(CliInputDependencies, RunSummaryOverAGltfBufferIsRefused) {
  write_gltf("g2.gltf", "g2.bin");
  const std::string bin = read("g2.bin");
  const auto r =
      run_here({"run", "g2.gltf", "-o", "out.off", "-n", "3", "-q", "--summary", "g2.bin"});
  expect_refused(r, {"--summary 'g2.bin'", "'g2.gltf' reads", "the input needs this file"},
                 "g2.bin", bin, {"g2.bin", "g2.gltf"});
  EXPECT_EQ(run_here({"check", "g2.gltf"}).exit_code, 0);
}

TEST_F(CliInputDependencies, RegionsFaceListOverAGltfBufferIsRefused) {
  write_gltf("g2.gltf", "g2.bin");
  const std::string bin = read("g2.bin");
  const auto r = run_here({"regions", "g2.gltf", "--face-list", "./g2.bin"});
  expect_refused(r, {"--face-list './g2.bin'", "'g2.gltf' reads"}, "g2.bin", bin,
                 {"g2.bin", "g2.gltf"});
}

TEST_F(CliInputDependencies, RunOutputsOverAnObjLibraryAndItsImagesAreRefused) {
  write_obj();
  const std::vector<std::string> before = listing();
  const std::string mtl = read("c.mtl"), png = read("tex.png"), bump = read("normal map.png");
  auto r = run_here({"run", "c.obj", "-o", "o.obj", "-n", "3", "-q", "--gltf", "a.glb", "--log",
                     "c.mtl", "--summary", "tex.png"});
  expect_refused(r, {"--log 'c.mtl'", "the material library that 'c.obj' reads (mtllib, line"},
                 "c.mtl", mtl, before);
  EXPECT_EQ(read("tex.png"), png);
  r = run_here({"run", "c.obj", "-o", "o.obj", "-n", "3", "-q", "--summary", "tex.png"});
  expect_refused(
      r, {"--summary 'tex.png'", "'c.mtl', the material library of 'c.obj'", "(map_Kd, line 3)"},
      "tex.png", png, before);
  // A texture the glTF export does not use is the OBJ's all the same.
  r = run_here({"run", "c.obj", "-o", "o.obj", "-n", "3", "-q", "--checkpoint", "normal map.png"});
  expect_refused(r, {"--checkpoint 'normal map.png'", "(bump, line 5)"}, "normal map.png", bump,
                 before);
  // Another name of the same file (a hard link) is the same file.
  fs::create_hard_link(dir_ / "c.mtl", dir_ / "link.off");
  r = run_here({"repair", "c.obj", "-o", "link.off"});
  expect_refused(r, {"-o 'link.off'", "'c.obj' reads"}, "c.mtl", mtl,
                 {"c.mtl", "c.obj", "link.off", "normal map.png", "tex.png"});
}

TEST_F(CliInputDependencies, AMissingLibraryIsNotCreated) {
  // Creating the file that the mtllib line names would give the OBJ materials it never had.
  write_obj();
  fs::remove(dir_ / "c.mtl");
  const auto r = run_here({"run", "c.obj", "-o", "o.obj", "-n", "3", "-q", "--log", "c.mtl"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("--log 'c.mtl': is the material library that 'c.obj' reads"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "c.mtl"));
  EXPECT_FALSE(fs::exists(dir_ / "o.obj"));
}

TEST_F(CliInputDependencies, AnOutputOverAPlyTextureFileIsRefused) {
  const test::TexturedObj t = test::textured_uv_sphere();
  std::string ply = "ply\nformat ascii 1.0\ncomment TextureFile skin.png\nelement vertex " +
                    std::to_string(t.x.rows()) +
                    "\nproperty double x\nproperty double y\nproperty double z\n" +
                    "element face " + std::to_string(t.polygons.size()) +
                    "\nproperty list uchar int vertex_indices\nend_header\n";
  for (Eigen::Index i = 0; i < t.x.rows(); ++i)
    ply += std::to_string(t.x(i, 0)) + " " + std::to_string(t.x(i, 1)) + " " +
           std::to_string(t.x(i, 2)) + "\n";
  for (const auto& p : t.polygons) {
    ply += std::to_string(p.size());
    for (const auto& c : p) ply += " " + std::to_string(c[0]);
    ply += "\n";
  }
  write("m.ply", ply);
  write("skin.png", "\x89PNG\r\n\x1a\nskin");
  const std::string png = read("skin.png");
  auto r = run_here({"run", "m.ply", "-o", "o.ply", "-n", "3", "-q", "--log", "skin.png"});
  expect_refused(
      r,
      {"--log 'skin.png'", "the texture that 'm.ply' names (comment TextureFile, header line 3)"},
      "skin.png", png, {"m.ply", "skin.png"});
  // A frame of --export-dir by the name of a texture that does not exist yet.
  fs::create_directories(dir_ / "frames");
  ply.replace(ply.find("skin.png"), 8, "frames/o_2.off");
  write("m.ply", ply);
  r = run_here({"run", "m.ply", "-o", "o.off", "-n", "2", "-q", "--export-dir", "frames"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(
      r.output.find("--export-dir 'frames': a frame (or the folder) would be 'frames/o_2.off'"),
      std::string::npos)
      << r.output;
  EXPECT_TRUE(fs::is_empty(dir_ / "frames"));
}

TEST_F(CliInputDependencies, AnOutputOverAGltfImageIsRefused) {
  write_gltf("g.gltf", "g.bin", "\"images\":[{\"uri\":\"my%20skin.png\"}]");
  write("my skin.png", "\x89PNG\r\n\x1a\nskin");
  const std::string png = read("my skin.png");
  const auto r =
      run_here({"run", "g.gltf", "-o", "out.off", "-n", "3", "-q", "--summary", "my skin.png"});
  expect_refused(r, {"--summary 'my skin.png'", "an image that 'g.gltf' names (images[0].uri)"},
                 "my skin.png", png, {"g.bin", "g.gltf", "my skin.png"});
}

TEST_F(CliInputDependencies, AnImageUriWithAQueryOrFragmentGuardsItsFile) {
  // A viewer loads tex.png for "tex.png?v=1" and "tex.png#x"; --log tex.png had replaced it.
  for (const std::string uri : {"tex.png?v=1", "tex.png#x"}) {
    write_gltf("g.gltf", "g.bin", "\"images\":[{\"uri\":\"" + uri + "\"}]");
    write("tex.png", "\x89PNG\r\n\x1a\ntex");
    const std::string png = read("tex.png");
    const auto r =
        run_here({"run", "g.gltf", "-o", "out.off", "-n", "3", "-q", "--log", "tex.png"});
    expect_refused(r, {"--log 'tex.png'", "an image that 'g.gltf' names (images[0].uri)"},
                   "tex.png", png, {"g.bin", "g.gltf", "tex.png"});
  }
}

TEST_F(CliInputDependencies, AnOutputOverAGlbExternalBufferIsRefused) {
  test::GltfScene s;
  s.primitives.push_back(test::octahedron_primitive(false, false));
  test::GltfParts parts = test::gltf_parts(s);
  write("ext.bin", parts.bin);
  // The buffer is the file ext.bin, not a BIN chunk (glb_bytes drops the %URI% mark).
  parts.json.replace(parts.json.find("%URI%"), 5, ",\"uri\":\"ext.bin\"%URI%");
  parts.bin.clear();
  write("e.glb", test::glb_bytes(parts));
  ASSERT_EQ(run_here({"check", "e.glb"}).exit_code, 0);
  const std::string bin = read("ext.bin");
  const auto r = run_here({"run", "e.glb", "-o", "out.off", "-n", "3", "-q", "--log", "ext.bin"});
  expect_refused(r, {"--log 'ext.bin'", "'e.glb' reads"}, "ext.bin", bin, {"e.glb", "ext.bin"});
}

}  // namespace
}  // namespace shellcontract
