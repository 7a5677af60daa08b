// Mesh files read the same whatever C locale the host program set (core/decimal_text.hpp): under
// a decimal-comma LC_NUMERIC, std::strtod, which the ASCII PLY reader and the PLY and OBJ
// documents (write_mesh's like=) read numbers with, stopped at the '.': every file with a
// decimal was refused ("'0.5' is not a number"), and the OFF and OBJ readers' strtod fallback
// read "1,0" as 1 where the CLI (always in the "C" locale) refuses it. Checked to fail on the
// code before parse_c_number (PLY and documents refused, the comma files read).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/decimal_text.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/comma_locale.hpp"
#include "support/scratch_dir.hpp"

namespace shellcontract {
namespace {

// An octahedron whose coordinates need their decimals: a point read as a stop gives 0.
const char* const PLY_HEAD =
    "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\n"
    "property float z\nelement face 8\nproperty list uchar int vertex_indices\nend_header\n";
const char* const VERTICES = "0.5 0 0\n-0.5 0 0\n0 1.5 0\n0 -1.5 0\n0 0 0.25\n0 0 -0.25\n";
const char* const PLY_FACES =
    "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n";
const char* const OBJ_FACES =
    "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";

/// The file's 18 coordinates, sorted (the reader may reorder vertices).
std::vector<double> expected_coordinates() {
  std::vector<double> c = {0.5, 0, 0, -0.5, 0, 0, 0, 1.5, 0, 0, -1.5, 0, 0, 0, 0.25, 0, 0, -0.25};
  std::sort(c.begin(), c.end());
  return c;
}

std::vector<double> sorted_coordinates(const Positions& x) {
  std::vector<double> c(x.data(), x.data() + x.size());
  std::sort(c.begin(), c.end());
  return c;
}

std::string obj_text() {
  std::string t;
  std::string v = VERTICES;
  for (std::size_t at = 0; at < v.size();) {
    const std::size_t end = v.find('\n', at);
    t += "v " + v.substr(at, end - at) + "\n";
    at = end + 1;
  }
  return t + OBJ_FACES;
}

class CommaLocaleMeshTest : public test::ScratchDirTest {
 protected:
  CommaLocaleMeshTest() : ScratchDirTest("comma_locale_mesh_") {}
};

TEST_F(CommaLocaleMeshTest, TheLocaleMadeReadsACommaWithStrtod) {
  SET_COMMA_LOCALE_OR_SKIP();
  // The condition of the host program: the C library's own reading follows the locale.
  EXPECT_EQ(std::strtod("0,5", nullptr), 0.5);
  EXPECT_EQ(std::strtod("0.5", nullptr), 0.0);
  double v = 0.0;
  ASSERT_TRUE(parse_c_number("0.5", v));
  EXPECT_EQ(v, 0.5);
  EXPECT_FALSE(parse_c_number("0,5", v));
  EXPECT_EQ(fixed_text(0.5, 4), "0.5000");
  EXPECT_EQ(general_text(0.00645, 3), "0.00645");
}

TEST_F(CommaLocaleMeshTest, AsciiPlyReadsItsDecimals) {
  const std::string path = write("m.ply", std::string(PLY_HEAD) + VERTICES + PLY_FACES);
  SET_COMMA_LOCALE_OR_SKIP();
  const Mesh mesh = read_input_mesh(path);
  EXPECT_EQ(sorted_coordinates(positions_from_mesh(mesh)), expected_coordinates());
}

TEST_F(CommaLocaleMeshTest, PlyAndObjDocumentsReadTheirDecimals) {
  // The documents write_mesh(like=) keeps: parsed, and written back with a point.
  const std::string ply = std::string(PLY_HEAD) + VERTICES + PLY_FACES;
  SET_COMMA_LOCALE_OR_SKIP();
  Positions x(6, 3);
  x << 0.75, 0, 0, -0.75, 0, 0, 0, 1.5, 0, 0, -1.5, 0, 0, 0, 0.25, 0, 0, -0.25;
  const auto ply_doc = parse_ply_document("m.ply", ply);
  EXPECT_NE(ply_doc->text(x).find("\n0.75 0 0\n"), std::string::npos) << ply_doc->text(x);
  const auto obj_doc = parse_obj_document("m.obj", obj_text());
  EXPECT_NE(obj_doc->text(x).find("v 0.75 0 0\n"), std::string::npos) << obj_doc->text(x);
}

TEST_F(CommaLocaleMeshTest, ObjReadsItsDecimals) {
  const std::string path = write("m.obj", obj_text());
  SET_COMMA_LOCALE_OR_SKIP();
  EXPECT_EQ(sorted_coordinates(positions_from_mesh(read_input_mesh(path))), expected_coordinates());
}

TEST_F(CommaLocaleMeshTest, ADecimalCommaIsRefusedAsTheCliRefusesIt) {
  // "1,0" is no number in the "C" locale, where the CLI runs: the module gives the same answer.
  const std::string off =
      write("comma.off",
            "OFF\n6 8 0\n1,0 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n"
            "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n");
  std::string comma_ply = std::string(PLY_HEAD) + VERTICES + PLY_FACES;
  comma_ply.replace(comma_ply.find("0.5 0 0"), 3, "0,5");
  const std::string ply = write("comma.ply", comma_ply);
  std::string comma_obj = obj_text();
  comma_obj.replace(comma_obj.find("0.5"), 3, "0,5");
  const std::string obj = write("comma.obj", comma_obj);
  SET_COMMA_LOCALE_OR_SKIP();
  for (const std::string& path : {off, ply, obj}) {
    try {
      read_input_mesh(path);
      ADD_FAILURE() << path << " was read";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("not a number"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace shellcontract
