// The values of an ascii PLY element: one line per element instance, and a value of an integer
// type that is an integer the type holds. Before, the reader read a stream of tokens (a value too
// many on a vertex line shifted every later value, and the message named a later face) and read
// '0.5' for an `int x` as 0.5 (the PLY document then wrote the result back as integers). And
// the PLY document writes an integer-typed x, y, z (and nx, ny, nz) back as double.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <cstring>
#include <string>

#include "mesh/ply_reader.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

const char* HEAD_FLOAT =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float "
    "z\n"
    "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
// Lines 10 to 13: the vertices; lines 14 to 17: the faces.
const char* TET_VERTICES = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
const char* TET_FACES = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const std::size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

std::string tet(const std::string& head = HEAD_FLOAT) { return head + TET_VERTICES + TET_FACES; }

/// The message of read_ply's InputError ("" if it read the bytes).
std::string refusal(const std::string& bytes) {
  try {
    read_ply("t.ply", bytes);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(PlyValues, AValueTooManyOnAVertexLineNamesThatVertexAndLine) {
  ASSERT_EQ(refusal(tet()), "");
  // Before: "degenerate face: face 0 (line 14) has 0 vertices" from the checks, or a list length
  // of -0.4 with one extra value on every line.
  EXPECT_EQ(refusal(replaced(tet(), "0 0 0\n", "0 0 0 1\n")),
            "t.ply: parse error: 'vertex' element 0 (line 10) has 4 values, but its header "
            "declares 3 properties");
  EXPECT_EQ(refusal(replaced(tet(), "0 0 1\n", "0 0 1 7 8\n")),
            "t.ply: parse error: 'vertex' element 3 (line 13) has 5 values, but its header "
            "declares 3 properties");
}

TEST(PlyValues, AValueTooFewOnAVertexLineNamesThatVertexAndLine) {
  EXPECT_EQ(refusal(replaced(tet(), "0 1 0\n", "0 1\n")),
            "t.ply: parse error: 'vertex' element 2 (line 12) has 2 values, but its header "
            "declares 3 properties");
}

TEST(PlyValues, AFaceLineMustHoldItsListLengthAndItsItems) {
  EXPECT_EQ(refusal(replaced(tet(), "3 0 1 3\n", "3 0 1 3 2\n")),
            "t.ply: parse error: 'face' element 1 (line 15) has 5 values, but its header's "
            "properties take 4 "
            "(a list: its length, then its items)");
  EXPECT_EQ(refusal(replaced(tet(), "3 0 1 3\n", "3 0 1\n")),
            "t.ply: parse error: 'face' element 1 (line 15) has 3 values, but its header's "
            "properties take 4 "
            "(a list: its length, then its items)");
}

TEST(PlyValues, BlankLinesAndAFileCutShortAreNotValueCounts) {
  // Blank lines between elements and blanks around the values are layout, not values.
  ASSERT_EQ(refusal(replaced(tet(), "1 0 0\n", "\n  1\t0 0  \r\n\n")), "");
  // The last line cut short is a truncated file, as before.
  const std::string cut = tet().substr(0, tet().size() - 3);
  EXPECT_EQ(refusal(cut).rfind("t.ply: truncated file: ", 0), 0u) << refusal(cut);
  EXPECT_EQ(refusal(tet().substr(0, tet().size() - 2))
                .rfind("t.ply: truncated file: the file ends before", 0),
            0u);
}

TEST(PlyValues, AnAsciiIntegerPropertyMustHoldAnIntegerOfItsType) {
  const std::string head = replaced(HEAD_FLOAT, "property float x", "property int x");
  ASSERT_EQ(refusal(tet(head)), "");
  // Before: read as -0.25 (a face index of 0.5 was already refused).
  EXPECT_EQ(refusal(replaced(tet(head), "1 0 0\n", "-0.25 0 0\n")),
            "t.ply: parse error: line 11: property 'x' of 'vertex' element 1 is '-0.25', not an "
            "integer from "
            "-2147483648 to 2147483647 (the header declares it int)");
  // Any integer-typed property, read or skipped; and the type's range.
  const std::string colour =
      replaced(HEAD_FLOAT, "property float z\n", "property float z\nproperty uchar red\n");
  const std::string coloured =
      std::string(colour) + "0 0 0 0\n1 0 0 255\n0 1 0 7\n0 0 1 3\n" + TET_FACES;
  ASSERT_EQ(refusal(coloured), "");
  EXPECT_EQ(refusal(replaced(coloured, "1 0 0 255\n", "1 0 0 256\n")),
            "t.ply: parse error: line 12: property 'red' of 'vertex' element 1 is '256', not an "
            "integer from 0 to "
            "255 (the header declares it uchar)");
  EXPECT_NE(refusal(replaced(coloured, "0 1 0 7\n", "0 1 0 0.5\n")).find("'0.5', not an integer"),
            std::string::npos);
  // The message of a face index stays the index's own.
  EXPECT_NE(refusal(replaced(tet(), "3 0 2 1\n", "3 0 2 0.5\n"))
                .find("vertex index 2 of face 0 is 0.5, not a non-negative integer"),
            std::string::npos);
}

TEST(PlyValues, IntegerCoordinatesAreWrittenBackAsDouble) {
  // `property int x` and `short y`: the result's positions were written as the nearest integers
  // (a mesh of unit size flattened); now the header says double, and they read back bitwise.
  std::string head = replaced(HEAD_FLOAT, "property float x", "property int x");
  head = replaced(head, "property float y", "property short y");
  head = replaced(head, "property float z\n", "property float z\nproperty uchar red\n");
  const std::string in = head + "0 0 0 9\n1 0 0 8\n0 1 0 7\n0 0 1 6\n" + TET_FACES;
  const auto doc = parse_ply_document("t.ply", in);
  Positions y(4, 3);
  y << 0.1, -0.2, 0.3, 1.25, 0.01, -0.125, 0.1 / 3.0, 0.9, 0.02, -0.01, 0.03, 0.7;
  const std::string out = doc->text(y);
  EXPECT_NE(
      out.find("property double x\nproperty double y\nproperty float z\nproperty uchar red\n"),
      std::string::npos)
      << out;
  const PlyData d = read_ply("out.ply", out);
  for (int i = 0; i < 4; ++i) {
    const auto& p = d.points[static_cast<std::size_t>(i)];
    EXPECT_EQ(p[0], y(i, 0));
    EXPECT_EQ(p[1], y(i, 1));
    EXPECT_EQ(static_cast<float>(p[2]), static_cast<float>(y(i, 2)));
  }
  // The other values are kept as written.
  EXPECT_NE(out.find(" 9\n"), std::string::npos);
  EXPECT_NE(out.find(" 6\n3 0 2 1\n"), std::string::npos);
}

TEST(PlyValues, BinaryIntegerCoordinatesAreWrittenBackAsDouble) {
  // Little-endian int16 x y z, a uchar after them: each coordinate grows from 2 to 8 bytes.
  std::string in =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty short x\nproperty short y\n"
      "property short z\nproperty uchar flag\nelement face 4\nproperty list uchar int "
      "vertex_indices\nend_header\n";
  const std::int16_t v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int i = 0; i < 4; ++i) {
    in.append(reinterpret_cast<const char*>(v[i]), 6);  // little-endian, as the test machines
    in += static_cast<char>(40 + i);
  }
  const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& t : f) {
    in += '\3';
    in.append(reinterpret_cast<const char*>(t), 12);
  }
  const auto doc = parse_ply_document("t.ply", in);
  Positions y(4, 3);
  y << 0.5, 0.25, -0.125, 3.75, 0.01, 0.02, 0.03, 40000.5, 0.04, 0.05, 0.06, -1e-3;
  const std::string out = doc->text(y);
  EXPECT_NE(
      out.find("property double x\nproperty double y\nproperty double z\nproperty uchar flag\n"),
      std::string::npos);
  const PlyData d = read_ply("out.ply", out);
  ASSERT_EQ(d.points.size(), 4u);
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(d.points[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)], y(i, k));
  ASSERT_EQ(d.faces.size(), 4u);
  EXPECT_EQ(d.faces[3], (std::vector<std::size_t>{1, 2, 3}));
  // The flags follow their vertex's 24 bytes of coordinates.
  const std::size_t body = out.find("end_header\n") + 11;
  EXPECT_EQ(out[body + 24], '\x28');
  EXPECT_EQ(out[body + 3 * 25 + 24], '\x2b');
}

TEST(PlyValues, BinaryIntegerNormalsAreWrittenBackAsDouble) {
  // Little-endian char nx ny nz between float x y z and a uchar: a new unit normal rounded to an
  // integer was -1, 0 or 1 (each vertex's normal a lattice direction, exit 0). Now the header
  // says double and each vertex's normal is its faces' normalized cross-product sum at the new
  // positions (computed here). Vertex 4 is in no face: it has no new normal and keeps the file's
  // value, now as 8 bytes, so that every later byte is still where the header says.
  std::string in =
      "ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float x\n"
      "property float y\nproperty float z\nproperty char nx\nproperty char ny\nproperty char nz\n"
      "property uchar flag\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
  const float v[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {2, 2, 2}};
  for (int i = 0; i < 5; ++i) {
    in.append(reinterpret_cast<const char*>(v[i]), 12);  // little-endian, as the test machines
    in += std::string{'\0', '\0', '\1'};                 // every normal +z
    in += static_cast<char>(40 + i);
  }
  const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& t : f) {
    in += '\3';
    in.append(reinterpret_cast<const char*>(t), 12);
  }
  const auto doc = parse_ply_document("t.ply", in);
  Positions y(5, 3);
  y << 0.1, -0.2, 0.3, 1.25, 0.01, -0.125, 0.1 / 3.0, 0.9, 0.02, -0.01, 0.03, 0.7, 2, 2, 2;
  const std::string out = doc->text(y);
  EXPECT_NE(out.find("property float z\nproperty double nx\nproperty double ny\n"
                     "property double nz\nproperty uchar flag\n"),
            std::string::npos)
      << out;
  const PlyData d = read_ply("out.ply", out);
  ASSERT_EQ(d.normals.size(), 5u);
  ASSERT_EQ(d.faces.size(), 4u);
  EXPECT_EQ(d.faces[3], (std::vector<std::size_t>{1, 2, 3}));
  for (int i = 0; i < 4; ++i) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const auto& t : f)
      if (t[0] == i || t[1] == i || t[2] == i) {
        const Eigen::Vector3d a = y.row(t[0]), b = y.row(t[1]), c = y.row(t[2]);
        sum += (b - a).cross(c - a);
      }
    const auto& n = d.normals[static_cast<std::size_t>(i)];
    EXPECT_NEAR((Eigen::Vector3d(n[0], n[1], n[2]) - sum.normalized()).norm(), 0.0, 1e-12)
        << "vertex " << i;
  }
  EXPECT_EQ(d.normals[4], (std::array<double, 3>{0, 0, 1}));
  // Each record: 12 bytes of x y z, 24 of normals, the flag.
  const std::size_t body = out.find("end_header\n") + 11;
  for (int i = 0; i < 5; ++i)
    EXPECT_EQ(out[body + 37 * static_cast<std::size_t>(i) + 36], static_cast<char>(40 + i));
}

TEST(PlyValues, IntegerNormalsStayAsTheyAreWhenNotEveryVertexHasOne) {
  // Only nx and ny (no nz): the document writes no normals, so their integer type and values
  // are kept (a header widened without its values would misread every later byte).
  std::string head = replaced(HEAD_FLOAT, "property float z\n",
                              "property float z\nproperty int nx\nproperty int ny\n");
  const std::string in = head + "0 0 0 0 1\n1 0 0 0 1\n0 1 0 0 1\n0 0 1 0 1\n" + TET_FACES;
  const auto doc = parse_ply_document("t.ply", in);
  Positions y(4, 3);
  y << 0.1, -0.2, 0.3, 1.25, 0.01, -0.125, 0.1 / 3.0, 0.9, 0.02, -0.01, 0.03, 0.7;
  const std::string out = doc->text(y);
  EXPECT_NE(out.find("property int nx\nproperty int ny\n"), std::string::npos) << out;
  EXPECT_NE(out.find(" 0 1\n3 0 2 1\n"), std::string::npos) << out;
}

}  // namespace
}  // namespace shellcontract
