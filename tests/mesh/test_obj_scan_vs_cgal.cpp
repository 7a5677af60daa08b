// The OBJ scan reads OBJ files itself (mesh/obj_scan.hpp says why not through CGAL): on valid files
// it must read exactly the points and faces CGAL::IO::read_OBJ reads, bit for bit, CGAL's reader
// being the independent answer; and it skips and refuses the statements CGAL's reader does.
#include <gtest/gtest.h>

#include <CGAL/IO/OBJ.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/obj_scan.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh.hpp"

namespace shellcontract {
namespace {

void expect_same_as_cgal(const std::string& text, const std::string& label) {
  const ObjScan scan = scan_obj(label, text);
  std::vector<Point3> points;
  std::vector<std::vector<std::size_t>> faces;
  std::istringstream in(text);
  ASSERT_TRUE(CGAL::IO::read_OBJ(in, points, faces)) << label << ": CGAL refuses the test file";
  ASSERT_EQ(scan.points.size(), points.size()) << label;
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int d = 0; d < 3; ++d)
      EXPECT_EQ(scan.points[i][static_cast<std::size_t>(d)], points[i][d]) << label << ": vertex " << i;
  EXPECT_EQ(scan.faces, faces) << label;
  EXPECT_EQ(scan.lines.vertex_line.size(), scan.points.size()) << label;
  EXPECT_EQ(scan.lines.face_line.size(), scan.faces.size()) << label;
}

const std::string TETRA_V = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";

TEST(ObjScanAgainstCgal, EveryCornerFormAndStatementReadsTheSamePointsAndFaces) {
  expect_same_as_cgal(TETRA_V + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n", "plain");
  expect_same_as_cgal(TETRA_V + "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n"
                                "f 1/1 3/3 2/2\nf 1/1/1 2/2/1 4/3/1\nf 1//1 4//1 3//1\nf 2/2/1 3/3/1 4/1/1\n",
                      "v/vt, v/vt/vn and v//vn corners");
  expect_same_as_cgal(TETRA_V + "f -4 -2 -3\nf -4 -3 -1\nf 1 -1 3\nf -3 -2 -1\n", "relative indices");
  expect_same_as_cgal("f 1 3 2\nf 1 2 4\n" + TETRA_V + "f 1 4 3\nf 2 3 4\n", "faces before the vertices they name");
  expect_same_as_cgal("# comment\nmtllib a.mtl\no thing\ng one two\nusemtl red\ns 1\n#v 9 9 9\n\n"
                      "v 0 0 0 0.5 0.5 0.5\nv 1. 0 0 1 0 0\nv 0 +1 .0 0 1 0\nv 0 0 1e0\n"
                      "s off\nf 1 3 2 # a comment\nusemtl blue\nf 1 2 4\np 1\nf 1 4 3\nf 2 3 4\n",
                      "groups, materials, comments, vertex colours and number forms");
  expect_same_as_cgal("v\t0 0 0\r\nv 1\t0 0\r\nv 0 1 0\r\nv 0 0 1\r\nf 1 3 2\r\nf 1 2 4\r\nf 1 4 3\r\nf\t2 3 4\r\n",
                      "tabs and CRLF line ends");
  expect_same_as_cgal("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                      "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n",
                      "quads");
}

/// Coordinates of every magnitude, written with 17 significant digits: parsed to the same double.
TEST(ObjScanAgainstCgal, RandomCoordinatesParseToTheSameDoubles) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-300, 300);
  const int nv = 2000;
  std::string text;
  char buf[128];
  for (int i = 0; i < nv; ++i) {
    text += "v";
    for (int d = 0; d < 3; ++d) {
      const double e = i % 3 == 0 ? 0.0 : exponent(rng);
      std::snprintf(buf, sizeof buf, d == 0 ? " %.17g" : (d == 1 ? " %.17e" : " %.9g"), mantissa(rng) * std::pow(10.0, e));
      text += buf;
    }
    text += "\n";
  }
  for (int f = 1; f + 2 <= nv; ++f) text += "f " + std::to_string(f) + " " + std::to_string(f + 1) + " " + std::to_string(f + 2) + "\n";
  expect_same_as_cgal(text, "random coordinates");
}

/// A statement CGAL's reader refuses is refused, with its line (`l` aside: the next test).
TEST(ObjScanAgainstCgal, AStatementCgalRefusesIsRefusedWithItsLine) {
  for (const std::string statement : {"mg 1", "vx 1 2 3"}) {
    const std::string text = TETRA_V + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n" + statement + "\n";
    std::vector<Point3> points;
    std::vector<std::vector<std::size_t>> faces;
    std::istringstream in(text);
    EXPECT_FALSE(CGAL::IO::read_OBJ(in, points, faces)) << statement;
    try {
      scan_obj("t.obj", text);
      ADD_FAILURE() << statement << ": accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("line 9"), std::string::npos) << e.what();
    }
  }
}

/// The one statement read otherwise than CGAL reads it: a polyline `l` (Blender's OBJ exporters
/// write one for a loose edge of a closed mesh) is skipped as a point `p` is, where CGAL refuses
/// the file. Before, it was a parse error, and `repair` could not read the file either.
TEST(ObjScanAgainstCgal, APolylineIsSkippedAsAPointIs) {
  const std::string faces = "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  const ObjScan plain = scan_obj("t.obj", TETRA_V + faces);
  for (const std::string statement : {"l 1 2", "l 1 2 3 4 1", "l 1/1 2/2", "l -1 -2", "p 1"}) {
    std::vector<Point3> points;
    std::vector<std::vector<std::size_t>> faces_cgal;
    std::istringstream in(TETRA_V + faces + statement + "\n");
    // CGAL refuses the polyline, not the point: what `p` shows is CGAL's skip.
    EXPECT_EQ(CGAL::IO::read_OBJ(in, points, faces_cgal), statement[0] == 'p') << statement;
    for (const std::string& text :
         {TETRA_V + faces + statement + "\n", TETRA_V + statement + "\n" + faces}) {
      const ObjScan scan = scan_obj("t.obj", text);
      EXPECT_EQ(scan.points.size(), plain.points.size()) << statement;
      EXPECT_EQ(scan.faces, plain.faces) << statement;
    }
  }
}

}  // namespace
}  // namespace shellcontract
