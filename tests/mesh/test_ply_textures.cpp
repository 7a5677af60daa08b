// A PLY's texture files as its document reports them (docs/design/attributes.md, "Textures of a
// PLY"): MeshLab's `comment TextureFile <path>` header lines, in ascii and binary files alike,
// each face's integer `texnumber` choosing one (else every face the first), relative paths from
// the PLY's folder. Before, these comments were skipped and a PLY had no face materials.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "export/gltf_material.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/scratch_dir.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

const double TET[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const int TET_FACES[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

/// The header of a tetrahedron PLY; `extra` goes after its 'format' line (line 3 on), `face_extra`
/// after the face's vertex_indices.
std::string header(const std::string& format, const std::string& extra,
                   const std::string& face_extra) {
  return "ply\nformat " + format + " 1.0\n" + extra +
         "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 4\nproperty list uchar int vertex_indices\n" +
         face_extra + "end_header\n";
}

/// An ascii tetrahedron; face f's texnumber is texnumbers[f] when given.
std::string ascii_tet(const std::string& extra, const std::string& texnumber_type = "",
                      const std::vector<int>& texnumbers = {}) {
  std::ostringstream o;
  o << header("ascii", extra,
              texnumber_type.empty() ? "" : "property " + texnumber_type + " texnumber\n");
  for (const auto& v : TET) o << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
  for (std::size_t f = 0; f < 4; ++f) {
    o << "3 " << TET_FACES[f][0] << ' ' << TET_FACES[f][1] << ' ' << TET_FACES[f][2];
    if (!texnumber_type.empty()) o << ' ' << texnumbers[f];
    o << '\n';
  }
  return o.str();
}

class PlyTextures : public test::ScratchDirTest {
 protected:
  PlyTextures() : ScratchDirTest("shellcontract_ply_textures_") {}
  /// The face materials of the PLY `bytes` written as `name` in the scratch folder.
  FaceMaterials materials(const std::string& name, const std::string& bytes) {
    const std::string path = write(name, bytes);
    const Mesh mesh = read_input_mesh(path);
    const auto doc = read_mesh_document(path);
    EXPECT_TRUE(doc && doc->matches(mesh));
    return doc ? doc->face_materials(mesh) : FaceMaterials{};
  }
};

TEST_F(PlyTextures, TextureFileCommentsAreTheMaterialsAndTexnumberChoosesOne) {
  const std::string extra =
      "comment made by hand\n"
      "comment TextureFile  maps/a b.png \t\n"  // line 4: spaces inside the name are kept
      "comment TextureFiles not.png\n"          // another keyword
      "comment TextureFile /abs/b.jpg\n";       // line 6
  const FaceMaterials m = materials("t.ply", ascii_tet(extra, "int", {1, 0, 1, 7}));
  EXPECT_EQ(m.names, (std::vector<std::string>{"maps/a b.png", "/abs/b.jpg"}));
  ASSERT_EQ(m.textures.size(), 2u);
  EXPECT_EQ(fs::path(m.textures[0].path), dir_ / "maps" / "a b.png");
  EXPECT_EQ(m.textures[0].line, 4u);
  EXPECT_EQ(m.textures[1].path, "/abs/b.jpg");
  EXPECT_EQ(m.textures[1].line, 6u);
  EXPECT_EQ(m.face_material, (std::vector<int>{1, 0, 1, 7}));
  EXPECT_TRUE(m.libraries.empty());
  EXPECT_EQ(fs::path(m.source), dir_ / "t.ply");

  // Without texnumber, or with one that is not an integer: every face has the first texture.
  EXPECT_EQ(materials("n.ply", ascii_tet(extra)).face_material, (std::vector<int>(4, 0)));
  EXPECT_EQ(materials("f.ply", ascii_tet(extra, "float", {1, 1, 1, 1})).face_material,
            (std::vector<int>(4, 0)));
  // No TextureFile comment: no materials, whatever the faces say.
  EXPECT_TRUE(materials("none.ply", ascii_tet("comment plain\n", "int", {0, 0, 0, 0})).empty());
}

TEST_F(PlyTextures, ABinaryPlyNamesItsTexturesTheSameWay) {
  std::string bytes = header("binary_little_endian", "comment TextureFile tex.jpg\r\n",
                             "property uchar texnumber\n");
  auto put = [&](const void* p, std::size_t n) { bytes.append(static_cast<const char*>(p), n); };
  for (const auto& v : TET)
    for (const double c : v) {
      const auto f = static_cast<float>(c);
      put(&f, 4);
    }
  for (std::size_t f = 0; f < 4; ++f) {
    const std::uint8_t three = 3, tex = 0;
    put(&three, 1);
    for (const int v : TET_FACES[f]) {
      const std::int32_t i = v;  // little-endian on the machines the tests run on
      put(&i, 4);
    }
    put(&tex, 1);
  }
  const FaceMaterials m = materials("b.ply", bytes);
  EXPECT_EQ(m.names, (std::vector<std::string>{"tex.jpg"}));
  ASSERT_EQ(m.textures.size(), 1u);
  EXPECT_EQ(m.textures[0].line, 3u);
  EXPECT_EQ(fs::path(m.textures[0].path), dir_ / "tex.jpg");
  EXPECT_EQ(m.face_material, (std::vector<int>(4, 0)));
}

TEST_F(PlyTextures, TheGltfMaterialsWarnForATexnumberOutOfRangeAndANamelessTexture) {
  FaceMaterials fm;
  fm.names = {"", "unused.png", "t.png"};
  fm.textures = {{"", 3}, {(dir_ / "unused.png").string(), 4}, {(dir_ / "t.png").string(), 5}};
  fm.face_material = {2, 0, 9, -1, 2};
  fm.source = "s.ply";
  write("t.png", "\x89PNG\r\n\x1a\n and the rest");
  std::vector<std::string> w;
  const GltfFaceMaterials g = gltf_materials(fm, true, w);
  ASSERT_EQ(g.materials.size(), 2u);  // the nameless one and t.png; unused.png is not read
  EXPECT_TRUE(g.materials[0].image.empty());
  EXPECT_EQ(g.materials[1].name, "t.png");
  EXPECT_EQ(g.materials[1].image_mime_type, "image/png");
  EXPECT_EQ(g.face_material, (std::vector<int>{1, 0, -1, -1, 1}));
  ASSERT_EQ(w.size(), 2u) << ::testing::PrintToString(w);
  EXPECT_EQ(w[0],
            "s.ply: 2 of 5 faces have a texnumber that names none of the 3 TextureFile "
            "comments: they have no material in the glTF");
  EXPECT_EQ(w[1],
            "s.ply: line 3: TextureFile without a file name: the glTF's material has no texture");
}

TEST_F(PlyTextures, AResultInAnotherFolderNamesTheSameImages) {
  // in/t.ply names in/maps/a b.png (relative), a missing file and an absolute path; written to
  // out/sub/r.ply, the first becomes ../../in/maps/a b.png (the same image from there), the others
  // stay as read (a warning names the missing one's line); the rest of the file is text(x)'s.
  // Written beside its input, the file is text(x) itself. Before, every path was written as read,
  // so the result named no image from its own folder.
  fs::create_directories(dir_ / "in" / "maps");
  fs::create_directories(dir_ / "out" / "sub");
  write("in/maps/a b.png", "\x89PNG\r\n\x1a\n image");
  const std::string extra =
      "comment TextureFile maps/a b.png\n"  // line 3
      "comment TextureFile gone.png\n"      // line 4
      "comment TextureFile /abs/c.png\n";
  const std::string in = write("in/t.ply", ascii_tet(extra));
  const auto doc = read_mesh_document(in);
  ASSERT_TRUE(doc);
  Positions x(4, 3);
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 3; ++k) x(i, k) = 2.0 * TET[i][k];
  const std::string out = (dir_ / "out" / "sub" / "r.ply").string();
  std::vector<std::string> w;
  write_mesh_document_atomic(out, *doc, x, &w);
  std::string want = doc->text(x);
  const std::string from = "comment TextureFile maps/a b.png";
  want.replace(want.find(from), from.size(), "comment TextureFile ../../in/maps/a b.png");
  std::ifstream f(out, std::ios::binary);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(f), {}), want);
  ASSERT_EQ(w.size(), 1u) << ::testing::PrintToString(w);
  EXPECT_NE(w[0].find("t.ply: line 4: TextureFile 'gone.png'"), std::string::npos) << w[0];
  // The result's own document finds the image from its folder.
  const FaceMaterials m = read_mesh_document(out)->face_materials(read_input_mesh(out));
  ASSERT_EQ(m.textures.size(), 3u);
  EXPECT_TRUE(fs::equivalent(m.textures[0].path, dir_ / "in" / "maps" / "a b.png"));

  std::vector<std::string> none;
  EXPECT_EQ(doc->text_for((dir_ / "in" / "same.ply").string(), x, &none), doc->text(x));
  EXPECT_TRUE(none.empty());
}

}  // namespace
}  // namespace shellcontract
