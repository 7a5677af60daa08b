// The OBJ document: what the simulation does not use comes back verbatim, positions
// are the given ones bitwise, normals are those of the new positions, texture coordinates follow
// the simulation's triangles. Compared with what the generator wrote (tests/support/textured_obj.hpp)
// and with normals computed here from the polygons' vector areas, not with the code under test.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: temporary files of this process's own

#include <Eigen/Geometry>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/textured_obj.hpp"

namespace shellcontract {
namespace {

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

bool starts_with(const std::string& s, const char* p) { return s.rfind(p, 0) == 0; }

std::vector<double> numbers_after_key(const std::string& line) {
  std::istringstream in(line);
  std::string key;
  in >> key;
  std::vector<double> v;
  for (std::string t; in >> t;) v.push_back(std::strtod(t.c_str(), nullptr));
  return v;
}

/// The sphere's positions moved by a smooth random-looking field (no symmetry left).
Positions moved(const Positions& x) {
  Positions y = x;
  std::mt19937 rng(56);
  std::uniform_real_distribution<double> d(-0.05, 0.05);
  for (Eigen::Index i = 0; i < y.rows(); ++i)
    for (int k = 0; k < 3; ++k) y(i, k) = 0.8 * y(i, k) + d(rng);
  return y;
}

TEST(ObjDocument, EveryLineButVertexAndNormalComesBackVerbatim) {
  const test::TexturedObj t = test::textured_uv_sphere();
  const auto doc = parse_obj_document("sphere.obj", t.text);
  ASSERT_EQ(doc->vertex_count(), static_cast<std::size_t>(t.x.rows()));
  ASSERT_EQ(doc->polygon_count(), t.polygons.size());
  const Positions y = moved(t.x);
  const std::vector<std::string> in = lines_of(t.text), out = lines_of(doc->text(y));
  ASSERT_EQ(in.size(), out.size());
  Eigen::Index v = 0;
  std::size_t quads = 0;
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (starts_with(in[i], "v ")) {
      // The new position bitwise, and what followed x y z (a vertex colour) kept.
      const std::vector<double> a = numbers_after_key(out[i]), b = numbers_after_key(in[i]);
      ASSERT_EQ(a.size(), b.size()) << out[i];
      for (int k = 0; k < 3; ++k) EXPECT_EQ(a[static_cast<std::size_t>(k)], y(v, k)) << out[i];
      for (std::size_t k = 3; k < a.size(); ++k) EXPECT_EQ(a[k], b[k]) << out[i];
      ++v;
    } else if (!starts_with(in[i], "vn ")) {
      EXPECT_EQ(out[i], in[i]) << "line " << i + 1;
      quads += starts_with(in[i], "f ") && numbers_after_key(in[i]).size() == 4;
    }
  }
  EXPECT_EQ(v, t.x.rows());
  EXPECT_GT(quads, 0u);  // the quads are still quads
}

TEST(ObjDocument, SmoothNormalsAreTheAreaWeightedVertexNormalsOfTheNewPositions) {
  const test::TexturedObj t = test::textured_uv_sphere();
  const Positions y = moved(t.x);
  // Independent: each polygon's vector area (sum of its fan triangles' cross products, half of
  // it; the factor cancels), added to each of its vertices.
  std::vector<Vec3> expect(static_cast<std::size_t>(y.rows()), Vec3::Zero());
  for (const auto& p : t.polygons) {
    Vec3 area = Vec3::Zero();
    const Vec3 a = y.row(static_cast<Eigen::Index>(p[0][0])).transpose();
    for (std::size_t k = 1; k + 1 < p.size(); ++k)
      area += (y.row(static_cast<Eigen::Index>(p[k][0])).transpose() - a).cross(y.row(static_cast<Eigen::Index>(p[k + 1][0])).transpose() - a);
    for (const auto& c : p) expect[c[0]] += area;
  }
  const std::vector<std::string> out = lines_of(parse_obj_document("sphere.obj", t.text)->text(y));
  std::size_t j = 0;
  for (const std::string& l : out) {
    if (!starts_with(l, "vn ")) continue;
    const std::vector<double> n = numbers_after_key(l);
    ASSERT_EQ(n.size(), 3u);
    const Vec3 e = expect[j++].normalized();
    EXPECT_NEAR((Vec3(n[0], n[1], n[2]) - e).norm(), 0.0, 1e-13) << l;
  }
  EXPECT_EQ(j, static_cast<std::size_t>(y.rows()));
}

TEST(ObjDocument, HardEdgeNormalsTurnWithTheirFaces) {
  // A unit cube of quads, one normal per face shared by its four corners (hard edges).
  const std::string cube =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
      "vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 1 0 0\nvn 0 1 0\nvn -1 0 0\n"
      "f 1//1 4//1 3//1 2//1\nf 5//2 6//2 7//2 8//2\nf 1//3 2//3 6//3 5//3\n"
      "f 2//4 3//4 7//4 6//4\nf 3//5 4//5 8//5 7//5\nf 4//6 1//6 5//6 8//6\n";
  const auto doc = parse_obj_document("cube.obj", cube);
  Positions x(8, 3);
  x << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1;
  const Mat3 r = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Positions y = (x * r.transpose()).eval();  // rows rotated by r
  const std::vector<std::string> in = lines_of(cube), out = lines_of(doc->text(y));
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (!starts_with(in[i], "vn ")) continue;
    const std::vector<double> a = numbers_after_key(in[i]), b = numbers_after_key(out[i]);
    EXPECT_NEAR((r * Vec3(a[0], a[1], a[2]) - Vec3(b[0], b[1], b[2])).norm(), 0.0, 1e-14) << out[i];
  }
}

TEST(ObjDocument, TexcoordsFollowTheSimulationTriangles) {
  const test::TexturedObj t = test::textured_uv_sphere();
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("shellcontract_obj_document_uv_" + std::to_string(::getpid()) + ".obj");
  std::ofstream(path) << t.text;
  const Mesh mesh = read_input_mesh(path.string());
  const auto doc = read_mesh_document(path.string());
  std::filesystem::remove(path);
  ASSERT_TRUE(doc->matches(mesh));
  const CornerTexcoords tc = doc->texcoords(mesh);
  ASSERT_EQ(tc.face_uv.size(), mesh.number_of_faces());
  ASSERT_EQ(tc.uv.size(), t.uv.size());
  for (const FaceIndex f : mesh.faces()) {
    std::vector<std::size_t> fv;
    for (const VertexIndex v : vertices_around_face(mesh.halfedge(f), mesh)) fv.push_back(v.idx());
    // The generator's polygon that holds the triangle (unique on this sphere), and its corners' vt.
    int found = 0;
    for (const auto& p : t.polygons) {
      std::vector<std::size_t> uv_of(3, SIZE_MAX);
      for (const auto& c : p)
        for (int k = 0; k < 3; ++k)
          if (c[0] == fv[static_cast<std::size_t>(k)]) uv_of[static_cast<std::size_t>(k)] = c[1];
      if (uv_of[0] == SIZE_MAX || uv_of[1] == SIZE_MAX || uv_of[2] == SIZE_MAX) continue;
      ++found;
      for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(tc.face_uv[f.idx()][k], uv_of[k]) << "face " << f.idx();
    }
    EXPECT_EQ(found, 1) << "face " << f.idx();
  }
}

TEST(ObjDocument, RelativeIndicesNameTheSameCorners) {
  const auto absolute = parse_obj_document("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n");
  const auto relative = parse_obj_document("r.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf -3/-3 -2/-2 -1/-1\n");
  Positions x(3, 3);
  x << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  EXPECT_EQ(absolute->triangle_count(), 1u);
  EXPECT_EQ(relative->triangle_count(), 1u);
  // Same normal (0 0 1) from the same corners: the vn-less file has no normal line to write,
  // so compare the corners through the written text of a file with normals.
  const auto with_normals = parse_obj_document("n.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 1 0 0\nf -3//-1 -2//-1 -1//-1\n");
  EXPECT_NE(with_normals->text(x).find("vn 0 0 1\n"), std::string::npos) << with_normals->text(x);
}

TEST(ObjDocument, AnIndexOutOfRangeNamesTheLine) {
  try {
    parse_obj_document("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n# a comment\nf 1/1 2/2 3/3\n");
    FAIL() << "accepted a texture coordinate index beyond the vt lines";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.obj: index out of range: line 6: texture coordinate index 2"), std::string::npos) << e.what();
  }
}

TEST(ObjDocument, DoesNotMatchAnotherMesh) {
  const test::TexturedObj t = test::textured_uv_sphere(6, 8);
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("shellcontract_obj_document_other_" + std::to_string(::getpid()) + ".obj");
  std::ofstream(path) << test::textured_uv_sphere(8, 12).text;
  const Mesh other = read_input_mesh(path.string());
  std::filesystem::remove(path);
  EXPECT_FALSE(parse_obj_document("small.obj", t.text)->matches(other));
}

TEST(ObjDocument, WindowsLineEndsStay) {
  const std::string crlf = "o t\r\nv 0 0 0\r\nv 1 0 0\r\nv 0 1 0 \r\nvn 1 0 0\r\nf 1//1 2//1 3//1\r\n";
  Positions x(3, 3);
  x << 0, 0, 0, 2, 0, 0, 0, 2, 0;
  EXPECT_EQ(parse_obj_document("crlf.obj", crlf)->text(x),
            "o t\r\nv 0 0 0\r\nv 2 0 0\r\nv 0 2 0 \r\nvn 0 0 1\r\nf 1//1 2//1 3//1\r\n");
}

TEST(ObjDocument, WrongRowCountIsRefused) {
  const test::TexturedObj t = test::textured_uv_sphere();
  EXPECT_THROW(parse_obj_document("s.obj", t.text)->text(Positions::Zero(3, 3)), std::invalid_argument);
}

}  // namespace
}  // namespace shellcontract
