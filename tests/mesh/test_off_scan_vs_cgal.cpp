// The OFF scan reads OFF files itself (mesh/off_scan.hpp says why not through CGAL): on valid files
// of every variant it must read exactly the points and faces CGAL::IO::read_OFF reads, bit for bit,
// CGAL's reader being the independent answer.
#include <gtest/gtest.h>

#include <CGAL/IO/OFF.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/off_scan.hpp"
#include "shellcontract/mesh.hpp"

namespace shellcontract {
namespace {

void expect_same_as_cgal(const std::string& text, const std::string& label) {
  const OffScan scan = scan_off(label, text);
  std::vector<Point3> points;
  std::vector<std::vector<std::size_t>> faces;
  std::istringstream in(text);
  ASSERT_TRUE(CGAL::IO::read_OFF(in, points, faces)) << label << ": CGAL refuses the test file";
  ASSERT_EQ(scan.points.size(), points.size()) << label;
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int d = 0; d < 3; ++d)
      EXPECT_EQ(scan.points[i][static_cast<std::size_t>(d)], points[i][d]) << label << ": vertex " << i;
  EXPECT_EQ(scan.faces, faces) << label;
}

/// A tetrahedron in each OFF variant the scan reads (the prefixes C, N, ST, 4 and n).
TEST(OffScanAgainstCgal, EveryVariantReadsTheSamePointsAndFaces) {
  const std::string faces = "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
  expect_same_as_cgal("OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n" + faces, "OFF");
  expect_same_as_cgal("OFF 4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n" + faces, "counts on the header line");
  expect_same_as_cgal("# a comment\nOFF\n\n4 4 0 # counts\n0 0 0 # v0\n1e0 0 0\n\n0 1.0 0\n0 0 +1\n" + faces,
                      "comments and blank lines");
  expect_same_as_cgal("COFF\n4 4 6\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n0 0 1 9 9 9 255\n"
                      "3 0 2 1 1 0 0\n3 0 1 3 0 1 0\n3 1 2 3\n3 0 3 2 0.5 0.5 0.5 1\n",
                      "COFF with vertex and face colours");
  expect_same_as_cgal("NOFF\n4 4 6\n0 0 0 -1 -1 -1\n1 0 0 1 0 0\n0 1 0 0 1 0\n0 0 1 0 0 1\n" + faces, "NOFF");
  expect_same_as_cgal("STOFF\n4 4 6\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n0 0 1 1 1\n" + faces, "STOFF");
  expect_same_as_cgal("4OFF\n4 4 6\n0 0 0 2\n3 0 0 3\n0 1 0 0.1\n0 0 7 -7\n" + faces, "4OFF divides by w");
  expect_same_as_cgal("nOFF\n3\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n" + faces, "nOFF of dimension 3");
  expect_same_as_cgal("OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n4 0 2 1 3\n3 0 1 3\n3 1 2 3\n3 0 3 2\n",
                      "a quadrilateral");
}

/// Coordinates of every magnitude, written with 17 significant digits: parsed to the same double.
TEST(OffScanAgainstCgal, RandomCoordinatesParseToTheSameDoubles) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-300, 300);
  const int nv = 2000;
  std::string text = "OFF\n" + std::to_string(nv) + " " + std::to_string(nv - 2) + " 0\n";
  char buf[128];
  for (int i = 0; i < nv; ++i) {
    for (int d = 0; d < 3; ++d) {
      const double e = i % 3 == 0 ? 0.0 : exponent(rng);
      std::snprintf(buf, sizeof buf, d == 0 ? "%.17g" : (d == 1 ? " %.17e" : " %.9g"),
                    mantissa(rng) * std::pow(10.0, e));
      text += buf;
    }
    text += "\n";
  }
  for (int f = 0; f + 2 < nv; ++f) text += "3 " + std::to_string(f) + " " + std::to_string(f + 1) + " " + std::to_string(f + 2) + "\n";
  expect_same_as_cgal(text, "random coordinates");
}

}  // namespace
}  // namespace shellcontract
