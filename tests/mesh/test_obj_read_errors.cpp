// OBJ files that read_input_mesh refuses: every message names the file and the line, as for OFF
// and PLY (before, CGAL's OBJ reader gave "CGAL could not read it" for most of these, and the
// checks after it named faces and vertices without their lines).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <ostream>
#include <string>
#include <vector>

#include "shellcontract/error.hpp"
#include "shellcontract/face_error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/repair.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

/// A tetrahedron with a comment and a blank line first, so that line numbers are not `v` counts:
/// vertices on lines 3-6, faces on lines 7-10.
const std::string HEAD = "# tetrahedron\n\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
const std::string FACES = "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

struct ObjCase {
  std::string name, text;
  std::vector<std::string> expected;  ///< substrings of the message besides the file's name
  /// The faces a FaceListError names (an index out of range: its face, as OFF, PLY and arrays
  /// name it; before, a plain InputError); empty: any InputError.
  std::vector<std::size_t> faces = {};
};

void PrintTo(const ObjCase& c, std::ostream* os) { *os << c.name; }

class ObjReadErrors : public ::testing::TestWithParam<ObjCase> {};

TEST_P(ObjReadErrors, NameTheFileAndTheLine) {
  const ObjCase& c = GetParam();
  const fs::path dir = fs::temp_directory_path() / ("shellcontract_obj_errors_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / (c.name + ".obj")).string();
  std::ofstream(path, std::ios::binary) << c.text;
  try {
    read_input_mesh(path);
    ADD_FAILURE() << c.name << ": accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(path + ": ", 0), 0u) << msg;
    for (const std::string& s : c.expected) EXPECT_NE(msg.find(s), std::string::npos) << c.name << ": '" << s << "' not in: " << msg;
    if (!c.faces.empty()) {
      const auto* about_faces = dynamic_cast<const FaceListError*>(&e);
      ASSERT_NE(about_faces, nullptr) << c.name << ": no faces named as data";
      EXPECT_EQ(about_faces->faces(), c.faces) << c.name;
    }
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(
    Files, ObjReadErrors,
    ::testing::Values(
        ObjCase{"index_beyond",
                HEAD + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 9\n",
                {"vertex index out of range", "face 3 (line 10)", "vertex 9", "4 vertices"},
                {3}},
        // One past the last vertex: CGAL's range test let it through to the checks (no line).
        ObjCase{"index_one_past",
                HEAD + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 5\n",
                {"vertex index out of range", "face 3 (line 10)", "vertex 5", "4 vertices"},
                {3}},
        ObjCase{"index_zero",
                HEAD + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 0\n",
                {"vertex index out of range", "face 3 (line 10)", "index 0"},
                {3}},
        ObjCase{"relative_index_too_far",
                HEAD + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf -3 -2 -9\n",
                {"vertex index out of range", "face 3 (line 10)", "-9", "4 vertices"},
                {3}},
        ObjCase{"vertex_without_z",
                "# tetrahedron\n\nv 0 0 0\nv 1 0\nv 0 1 0\nv 0 0 1\n" + FACES,
                {"parse error", "vertex 1 (line 4)", "2 numbers"}},
        ObjCase{"vertex_token_not_a_number",
                "# tetrahedron\n\nv 0 0 0\nv 1 0 abc\nv 0 1 0\nv 0 0 1\n" + FACES,
                {"parse error", "vertex 1 (line 4)", "'abc' is not a number"}},
        ObjCase{"vertex_overflows",
                "# tetrahedron\n\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1e999\n" + FACES,
                {"non-finite coordinate", "vertex 3 (line 6)", "1e999"}},
        ObjCase{"corner_not_an_index",
                HEAD + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 x 4\n",
                {"parse error", "face 3 (line 10)", "'x'"}},
        ObjCase{
            "unknown_statement", HEAD + FACES + "xyz 1 2\n", {"parse error", "line 11", "'xyz'"}},
        // The checks after reading name the OBJ line too.
        ObjCase{"repeated_corner",
                HEAD + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 2 4\n",
                {"degenerate face", "face 3 (line 10)"}},
        ObjCase{"duplicate_face",
                HEAD + FACES + "f 2 3 4\n",
                {"duplicate face", "face 4 (line 11)", "(line 10)"}},
        ObjCase{"no_faces", HEAD, {"empty mesh", "0 faces"}}),
    [](const ::testing::TestParamInfo<ObjCase>& info) { return info.param.name; });

// Blender's OBJ exporters write a loose edge of a closed mesh as a polyline `l`; it was a parse
// error for `run` and for `repair`, which is there to make a refused file usable. It is skipped
// now, as a point `p` is: the surface is the file's faces, read as without the line.
TEST(ObjLooseEdge, APolylineIsSkippedByTheReaderAndByRepair) {
  const fs::path dir =
      fs::temp_directory_path() / ("shellcontract_obj_l_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / "loose_edge.obj").string();
  std::ofstream(path, std::ios::binary) << HEAD + FACES + "l 1 4\n";
  const Mesh m = read_input_mesh(path);
  EXPECT_EQ(m.number_of_vertices(), 4u);
  EXPECT_EQ(m.number_of_faces(), 4u);
  RepairReport report;
  const Mesh r = repair_input_mesh(path, &report);
  EXPECT_EQ(r.number_of_faces(), 4u);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace shellcontract
