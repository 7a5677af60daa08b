// OBJ files of many names (usemtl, g): what the document and the extras keep of them costs in
// proportion to the file. Before, each name was looked for among all the names so far, and each
// usemtl line searched the rest of the file for a comment: either ran far beyond the TIMEOUT of
// test_costs (tests/CMakeLists.txt) on these inputs, which take a small part of it now.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "mesh/file_extras.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/scratch_dir.hpp"

namespace shellcontract {
namespace {

const std::string TETRAHEDRON = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
const std::string FACES = "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

/// "m0000042": the i-th of the distinct names.
std::string name_of(std::size_t i) {
  char s[16];
  std::snprintf(s, sizeof s, "m%07zu", i);
  return s;
}

class ObjNameCosts : public test::ScratchDirTest {
 protected:
  ObjNameCosts() : ScratchDirTest("shellcontract_obj_name_costs_") {}
  /// The materials of the tetrahedron's faces, read from `text` through the document.
  FaceMaterials materials(const std::string& text) const {
    const std::string path = write("t.obj", text);
    const Mesh mesh = read_input_mesh(path);
    const auto doc = read_mesh_document(path);
    EXPECT_TRUE(doc && doc->matches(mesh));
    return doc ? doc->face_materials(mesh) : FaceMaterials{};
  }
};

// A million distinct usemtl names (16 MB): the names were searched for each (n^2 / 2 compares).
TEST_F(ObjNameCosts, DistinctMaterialNamesCostInProportionToTheFile) {
  const std::size_t n = 1000000;
  std::string text = TETRAHEDRON;
  text.reserve(16 * n);
  for (std::size_t i = 0; i < n; ++i) text += "usemtl " + name_of(i) + "\n";
  text += "usemtl " + name_of(7) + "\n" + FACES;  // a name used before keeps its index
  const FaceMaterials m = materials(text);
  ASSERT_EQ(m.names.size(), n);
  EXPECT_EQ(m.names.front(), name_of(0));
  EXPECT_EQ(m.names.back(), name_of(n - 1));
  EXPECT_EQ(m.face_material, (std::vector<int>{7, 7, 7, 7}));
}

// Four million usemtl lines of one name (36 MB) and no comment: each line looked for a '#' to
// the file's end. A comment on the last line still ends its name.
TEST_F(ObjNameCosts, AUsemtlLineLooksForItsCommentInItselfOnly) {
  const std::size_t n = 4000000;
  std::string text = TETRAHEDRON;
  text.reserve(9 * n + 64);
  for (std::size_t i = 0; i < n; ++i) text += "usemtl a\n";
  text += "f 1 3 2\nf 1 2 4\nf 1 4 3\nusemtl b # the last\nf 2 3 4\n";
  const FaceMaterials m = materials(text);
  EXPECT_EQ(m.names, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(m.face_material, (std::vector<int>{0, 0, 0, 1}));
}

// A `g` line of a million distinct names (9 MB): repair's list of what a plain output drops
// searched the names so far for each.
TEST(ObjNameCostsExtras, DistinctGroupNamesCostInProportionToTheFile) {
  const std::size_t n = 1000000;
  std::string text = TETRAHEDRON + "g";
  text.reserve(9 * n + 128);
  for (std::size_t i = 0; i < n; ++i) text += " " + name_of(i);
  text += " " + name_of(3) + "\n" + FACES;  // a name again is not counted again
  const FileExtras e = describe_file_extras("obj", text);
  EXPECT_EQ(e.items,
            (std::vector<std::string>{"1000000 groups (g m0000000, m0000001, m0000002, ...)"}));
}

}  // namespace
}  // namespace shellcontract
