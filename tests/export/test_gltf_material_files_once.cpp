// The files of an input's materials are read once however often they are named (review7 F5,
// F10): materials that name one texture share its bytes, and a library named on many mtllib
// lines (or by several spellings) is read and parsed once. Before, each material held a copy of
// its texture (80 materials on one 10 MB PNG took 870 MB for --gltf, 300 ran out of memory), and
// each mtllib name read its library again (1,000 names of a 5 MB library: 31 s).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "export/gltf_material.hpp"
#include "export_fixtures.hpp"
#include "gltf_reader.hpp"
#include "support/cli_runner.hpp"
#include "support/multi_material_sphere.hpp"
#include "support/textured_octahedron.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

std::size_t count(const std::vector<std::string>& ws, const std::string& s) {
  std::size_t n = 0;
  for (const std::string& w : ws) n += w.find(s) != std::string::npos ? 1 : 0;
  return n;
}

void write_png(const std::string& path, std::size_t padding = 0) {
  std::vector<unsigned char> bytes = test::tiny_png();
  bytes.resize(bytes.size() + padding, 0);  // after IEND: still a PNG by its signature
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
}

// A library named three times (twice as written, once as ./m.mtl) is parsed once: its bad line
// warns once, not three times, and the materials are those of one reading. The second library,
// named after it, still comes second (first definition wins).
TEST(MtlFilesOnce, ALibraryNamedManyTimesIsReadOnce) {
  test::ScratchDir dir("material_lib_once");
  std::ofstream(dir.file("m.mtl")) << "newmtl a\nKd 1 oops 0\nKd 1 0 0\n";
  std::ofstream(dir.file("n.mtl")) << "newmtl a\nKd 0 0 1\nnewmtl b\nKd 0 1 0\n";
  FaceMaterials fm;
  fm.names = {"a", "b"};
  fm.face_material = {0, 1, 0};
  const std::string again = (fs::path(dir.str()) / "." / "m.mtl").string();
  fm.libraries = {{dir.file("m.mtl"), 1, true},
                  {dir.file("m.mtl"), 2, true},
                  {again, 3, true},
                  {dir.file("n.mtl"), 4, true},
                  {dir.file("m.mtl"), 5, true}};
  fm.source = "x.obj";
  std::vector<std::string> w;
  const GltfFaceMaterials g = gltf_materials(fm, true, w);
  ASSERT_EQ(g.materials.size(), 2u);
  EXPECT_EQ(g.materials[0].base_colour, (std::array<double, 4>{1.0, 0.0, 0.0, 1.0}));
  EXPECT_EQ(g.materials[1].base_colour, (std::array<double, 4>{0.0, 1.0, 0.0, 1.0}));
  EXPECT_EQ(count(w, dir.file("m.mtl") + ": line 2: Kd"), 1u) << ::testing::PrintToString(w);
  EXPECT_EQ(w.size(), 1u) << ::testing::PrintToString(w);

  // A missing library named twice: one warning, at its first line.
  fm.libraries = {{dir.file("gone.mtl"), 1, false},
                  {dir.file("gone.mtl"), 2, false},
                  {dir.file("n.mtl"), 3, true}};
  w.clear();
  EXPECT_EQ(gltf_materials(fm, true, w).materials.size(), 2u);
  EXPECT_EQ(count(w, "x.obj: line 1: material library"), 1u) << ::testing::PrintToString(w);
  EXPECT_EQ(w.size(), 1u) << ::testing::PrintToString(w);
}

// Materials whose map_Kd (or a PLY's TextureFile comments) name one file, by any spelling, share
// one copy of its bytes; each keeps its own warnings.
TEST(MtlFilesOnce, MaterialsNamingOneTextureShareItsBytes) {
  test::ScratchDir dir("material_tex_once");
  write_png(dir.file("t.png"));
  std::ofstream(dir.file("m.mtl")) << "newmtl a\nmap_Kd t.png\nnewmtl b\nmap_Kd ./t.png\n"
                                      "newmtl c\nmap_Kd t.png\nnewmtl d\nmap_Kd gone.png\n"
                                      "newmtl e\nmap_Kd gone.png\n";
  FaceMaterials fm;
  fm.names = {"a", "b", "c", "d", "e"};
  fm.face_material = {0, 1, 2, 3, 4};
  fm.libraries = {{dir.file("m.mtl"), 1, true}};
  fm.source = "x.obj";
  std::vector<std::string> w;
  const GltfFaceMaterials g = gltf_materials(fm, true, w);
  ASSERT_EQ(g.materials.size(), 5u);
  ASSERT_FALSE(g.materials[0].image.empty());
  EXPECT_EQ(g.materials[0].image_mime_type, "image/png");
  EXPECT_TRUE(g.materials[0].image.shares(g.materials[1].image));
  EXPECT_TRUE(g.materials[0].image.shares(g.materials[2].image));
  EXPECT_EQ(g.materials[0].image, ImageBytes(test::tiny_png()));
  EXPECT_TRUE(g.materials[3].image.empty());
  EXPECT_EQ(count(w, "m.mtl: line 8: map_Kd"), 1u) << ::testing::PrintToString(w);
  EXPECT_EQ(count(w, "m.mtl: line 10: map_Kd"), 1u) << ::testing::PrintToString(w);
  EXPECT_EQ(w.size(), 2u) << ::testing::PrintToString(w);

  FaceMaterials ply;
  ply.names = {"t.png", "./t.png"};
  ply.textures = {{dir.file("t.png"), 3}, {(fs::path(dir.str()) / "." / "t.png").string(), 4}};
  ply.face_material = {0, 1};
  ply.source = "x.ply";
  w.clear();
  const GltfFaceMaterials p = gltf_materials(ply, true, w);
  ASSERT_EQ(p.materials.size(), 2u);
  EXPECT_TRUE(p.materials[0].image.shares(p.materials[1].image));
  EXPECT_TRUE(w.empty()) << ::testing::PrintToString(w);
}

/// The run's peak memory (MB) from its summary.
double peak_memory_mb(const std::string& summary) {
  std::ifstream in(summary);
  const std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t at = s.find("\"peak_memory_mb\": ");
  if (at == std::string::npos) return -1.0;
  return std::stod(s.substr(at + 18));
}

// The CLI's --gltf of an OBJ whose 48 materials all name one 4 MiB texture holds it once: the
// run's peak memory is that of the same OBJ with one material, within a few copies of the file
// (a copy per material, before, was 47 x 4 MiB more).
TEST(MtlFilesOnce, ManyMaterialsOnOneTextureHoldItOnceInTheCli) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  test::ScratchDir dir("material_tex_memory");
  constexpr std::size_t materials = 48, texture_mib = 4;
  write_png(dir.file("big.png"), texture_mib << 20);
  {
    std::ofstream mtl(dir.file("m.mtl"));
    for (std::size_t k = 0; k < materials; ++k) mtl << "newmtl m" << k << "\nmap_Kd big.png\n";
  }
  // The sphere's faces, each under material k % n (its own usemtl lines dropped).
  std::ifstream in(test::write_multi_material_sphere(dir.str(), "sphere"));
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);)
    if (l.rfind("usemtl", 0) != 0 && l.rfind("mtllib", 0) != 0) lines.push_back(l);
  const auto write_obj = [&](const std::string& name, std::size_t n) {
    std::ofstream obj(dir.file(name));
    obj << "mtllib m.mtl\n";
    std::size_t face = 0;
    for (const std::string& l : lines) {
      if (l.rfind("f ", 0) == 0) obj << "usemtl m" << face++ % n << '\n';
      obj << l << '\n';
    }
    return dir.file(name);
  };
  const auto peak = [&](const std::string& obj) {
    const auto r = test::run_cli({"run", obj, "-o", dir.file("out.obj"), "-n", "2", "-q", "--gltf",
                                  dir.file("run.glb"), "--summary", dir.file("s.json")});
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
    const tinygltf::Model m = test::load_glb(dir.file("run.glb"));
    EXPECT_EQ(m.images.size(), 1u);
    return peak_memory_mb(dir.file("s.json"));
  };
  const double one = peak(write_obj("one.obj", 1));
  const double many = peak(write_obj("many.obj", materials));
  ASSERT_GT(one, 0.0);
  EXPECT_LT(many - one, 8.0 * texture_mib)
      << "one material: " << one << " MB, " << materials << " materials: " << many << " MB";
}

}  // namespace
}  // namespace shellcontract
