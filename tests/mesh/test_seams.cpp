// Seams (mesh_io.hpp, "Seams"; docs/design/attributes.md): a mesh that is open only because its
// vertices are split at UV seams is read welded, gives its input's vertices and faces back to the
// outputs, and keeps its texture coordinates; a mesh closed as given is never welded, and one
// that welding does not close keeps its error. The split sphere (tests/support/seam_split.hpp)
// knows which closed-sphere vertex each of its vertices copies: the expectations come from it.
#include <CGAL/boost/graph/helpers.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/read_polygon_soup.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/face_error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/seam_split.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::SeamSplitMesh;
using test::seam_split_sphere;
using Tri = std::array<std::size_t, 3>;

class Seams : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("shellcontract_seams_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) const {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  fs::path dir_;
};

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

Mesh from_arrays(const SeamSplitMesh& m, InputReport* report = nullptr) {
  std::vector<std::int64_t> faces;
  for (const Tri& t : m.tris) faces.insert(faces.end(), t.begin(), t.end());
  TriangleSoupView s;
  s.vertices = m.x.data();
  s.num_vertices = static_cast<std::size_t>(m.x.rows());
  s.faces64 = faces.data();
  s.num_faces = m.tris.size();
  return mesh_from_arrays(s, "arrays", report);
}

/// What every welded mesh of `m` must be: its closed sphere, naming m's vertices and faces.
void expect_welded(const Mesh& mesh, const InputReport& report, const SeamSplitMesh& m) {
  const auto n = static_cast<std::size_t>(m.x.rows());
  ASSERT_LT(m.closed_vertices, n);  // the fixture has copies
  EXPECT_EQ(mesh.number_of_vertices(), m.closed_vertices);
  EXPECT_TRUE(CGAL::is_closed(mesh));
  EXPECT_TRUE(has_welded_seams(mesh));
  EXPECT_EQ(report.welded_vertices, n - m.closed_vertices);
  ASSERT_EQ(report.notes.size(), 1u);
  EXPECT_NE(report.notes[0].find(std::to_string(n - m.closed_vertices) + " seam vertices were welded"), std::string::npos)
      << report.notes[0];
  for (const std::string& w : report.warnings) EXPECT_EQ(w.find("seam"), std::string::npos) << w;  // a note
  EXPECT_GT(report.volume, 0.0);
  EXPECT_EQ(input_vertex_count(mesh), n);
  // Two vertices are welded exactly when they copy the same closed-sphere vertex.
  const std::vector<std::size_t> map = input_vertex_map(mesh);
  ASSERT_EQ(map.size(), n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < i; ++j) EXPECT_EQ(map[i] == map[j], m.closed_vertex[i] == m.closed_vertex[j]) << i << ", " << j;
  // Every copy back at its own position, bit for bit.
  const Positions back = input_positions(mesh, positions_from_mesh(mesh));
  ASSERT_EQ(back.rows(), m.x.rows());
  for (Eigen::Index i = 0; i < back.rows(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(back(i, k), m.x(i, k)) << "vertex " << i;
}

TEST_F(Seams, ASeamSplitFileIsReadWeldedAndNamesItsOwnVertices) {
  const SeamSplitMesh m = seam_split_sphere();
  for (const char* name : {"split.ply", "split.obj"}) {
    const std::string path = write(name, name[6] == 'p' ? m.ply() : m.obj());
    InputReport report;
    const Mesh mesh = read_input_mesh(path, &report);
    SCOPED_TRACE(name);
    expect_welded(mesh, report, m);
    EXPECT_FALSE(report.reoriented);
    EXPECT_EQ(input_faces(mesh), m.tris);  // face order and corner order as in the file
  }
}

TEST_F(Seams, AnInsideOutSplitFileIsWeldedAndItsCornersFollowTheFlip) {
  SeamSplitMesh m = seam_split_sphere();
  std::vector<Tri> flipped = m.tris;
  for (Tri& t : flipped) std::swap(t[1], t[2]);
  std::swap(m.tris, flipped);
  InputReport report;
  const Mesh mesh = read_input_mesh(write("inside_out.ply", m.ply()), &report);
  expect_welded(mesh, report, m);
  EXPECT_TRUE(report.reoriented);
  // The mesh's faces are flipped back; each corner still names the file's vertex there.
  const std::vector<Tri> corners = input_faces(mesh);
  for (std::size_t f = 0; f < corners.size(); ++f) EXPECT_EQ(corners[f], (Tri{m.tris[f][0], m.tris[f][2], m.tris[f][1]})) << f;
}

TEST_F(Seams, ArraysAreWeldedAsTheFileIs) {
  const SeamSplitMesh m = seam_split_sphere(5, 7);
  InputReport report, file_report;
  const Mesh mesh = from_arrays(m, &report);
  expect_welded(mesh, report, m);
  const Mesh file = read_input_mesh(write("split.ply", m.ply()), &file_report);
  EXPECT_EQ(input_faces(mesh), input_faces(file));
  EXPECT_EQ(positions_from_mesh(mesh), positions_from_mesh(file));
  EXPECT_EQ(report.volume, file_report.volume);
}

TEST_F(Seams, AClosedMeshIsNeverWeldedEvenWithVerticesAtOnePosition) {
  // Two tetrahedra touching at one point: closed as given, so the two vertices there stay two.
  const std::string path = write("touching.off",
                                 "OFF\n8 8 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 0 0\n-1 0 0\n0 -1 0\n0 0 -1\n"
                                 "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 4 6 5\n3 4 7 6\n3 4 5 7\n3 5 6 7\n");
  InputReport report;
  const Mesh mesh = read_input_mesh(path, &report);
  EXPECT_EQ(mesh.number_of_vertices(), 8u);
  EXPECT_FALSE(has_welded_seams(mesh));
  EXPECT_EQ(report.welded_vertices, 0u);
  EXPECT_TRUE(report.notes.empty());
  EXPECT_EQ(input_vertex_count(mesh), 8u);
  const Positions x = positions_from_mesh(mesh);
  EXPECT_EQ(input_positions(mesh, x), x);
}

TEST_F(Seams, AMeshThatWeldingDoesNotCloseKeepsItsErrorWithAHint) {
  SeamSplitMesh m = seam_split_sphere();
  m.tris.pop_back();  // a hole that no weld closes
  const std::string e = error_of([&] { read_input_mesh(write("holed.ply", m.ply())); });
  EXPECT_NE(e.find(": open boundary: "), std::string::npos) << e;
  EXPECT_NE(e.find("vertices are at the position of another vertex"), std::string::npos) << e;
  EXPECT_NE(e.find("after welding, open boundary"), std::string::npos) << e;
  EXPECT_NE(error_of([&] { from_arrays(m); }).find("after welding, open boundary"), std::string::npos);
  // Without copies, the error is what it always was: no hint.
  const std::string plain = error_of([&] {
    read_input_mesh(write("open.off", "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n"));
  });
  EXPECT_NE(plain.find(": open boundary: "), std::string::npos) << plain;
  EXPECT_EQ(plain.find("welding"), std::string::npos) << plain;
}

/// The refusal of f (a FaceListError): its message and faces.
std::pair<std::string, std::vector<std::size_t>> face_error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const FaceListError& e) {
    return {e.what(), e.faces()};
  } catch (const InputError& e) {
    return {std::string("(not a FaceListError) ") + e.what(), {}};
  }
  return {"(no error)", {}};
}

TEST_F(Seams, AHoleLeftAfterWeldingIsNamedByTheFacesAroundIt) {
  // A face away from the seams removed: the mesh as given is open along every seam and at the
  // hole, the welded one at the hole only. The refusal must lead to the hole: its faces are the
  // hole's neighbours (the faces that share an edge of the closed sphere with the removed one,
  // numbered as in the file without it), and its edge is named by the file's vertices.
  SeamSplitMesh m = seam_split_sphere();
  std::vector<std::size_t> copies(m.closed_vertices, 0);
  for (const std::size_t c : m.closed_vertex) ++copies[c];
  std::size_t hole = m.tris.size() / 2;
  const auto has_copy = [&](const Tri& t) {
    return std::any_of(t.begin(), t.end(),
                       [&](std::size_t v) { return copies[m.closed_vertex[v]] > 1; });
  };
  while (hole < m.tris.size() && has_copy(m.tris[hole])) ++hole;
  ASSERT_LT(hole, m.tris.size());
  const Tri removed = m.tris[hole];
  m.tris.erase(m.tris.begin() + static_cast<std::ptrdiff_t>(hole));
  const auto closed_edge = [&](std::size_t a, std::size_t b) {
    return std::minmax(m.closed_vertex[a], m.closed_vertex[b]);
  };
  std::set<std::pair<std::size_t, std::size_t>> hole_edges;
  for (std::size_t k = 0; k < 3; ++k)
    hole_edges.insert(closed_edge(removed[k], removed[(k + 1) % 3]));
  std::vector<std::size_t> around;
  for (std::size_t f = 0; f < m.tris.size(); ++f)
    for (std::size_t k = 0; k < 3; ++k)
      if (hole_edges.count(closed_edge(m.tris[f][k], m.tris[f][(k + 1) % 3]))) {
        around.push_back(f);
        break;
      }
  ASSERT_EQ(around.size(), 3u);

  const std::string path = write("holed.ply", m.ply());
  for (const auto& [what, faces] :
       {face_error_of([&] { read_input_mesh(path); }), face_error_of([&] { from_arrays(m); })}) {
    EXPECT_EQ(faces, around) << what;
    EXPECT_NE(what.find(": open boundary: "), std::string::npos) << what;
    EXPECT_NE(what.find("after welding, open boundary: "), std::string::npos) << what;
    // The first face left open, and an edge of the hole in the file's vertex numbers.
    EXPECT_NE(what.find(" of face " + std::to_string(around[0]) + " "), std::string::npos) << what;
    bool edge_named = false;
    for (std::size_t k = 0; k < 3; ++k)
      for (std::size_t j = 0; j < 3; ++j)
        edge_named = edge_named || what.find("edge (" + std::to_string(removed[k]) + ", " +
                                             std::to_string(removed[j]) + ")") != std::string::npos;
    EXPECT_TRUE(edge_named) << what;
    EXPECT_NE(what.find("(3 faces in all have such edges)"), std::string::npos) << what;
  }
}

TEST_F(Seams, OnlyBitwiseIdenticalPositionsAreWelded) {
  SeamSplitMesh m = seam_split_sphere();
  // A copy of the north pole (x = 0.0) given as x = -0.0: the same value, not the same bits.
  std::size_t copy = 0;
  while (!(m.x(static_cast<Eigen::Index>(copy), 2) == 1.0 && m.closed_vertex[copy] == 0)) ++copy;
  ASSERT_EQ(m.x(static_cast<Eigen::Index>(copy), 0), 0.0);
  m.x(static_cast<Eigen::Index>(copy), 0) = -0.0;
  std::ostringstream off;  // OFF keeps the sign of zero ("-0")
  off.precision(17);
  off << "OFF\n" << m.x.rows() << ' ' << m.tris.size() << " 0\n";
  for (Eigen::Index i = 0; i < m.x.rows(); ++i) off << m.x(i, 0) << ' ' << m.x(i, 1) << ' ' << m.x(i, 2) << '\n';
  for (const Tri& t : m.tris) off << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  const std::string e = error_of([&] { read_input_mesh(write("signed_zero.off", off.str())); });
  EXPECT_NE(e.find("after welding, open boundary"), std::string::npos) << e;
}

TEST_F(Seams, AWeldedMeshIsWrittenWithItsInputsVerticesAndFaces) {
  const SeamSplitMesh m = seam_split_sphere();
  const Mesh mesh = read_input_mesh(write("split.ply", m.ply()));
  Positions x = positions_from_mesh(mesh);
  x *= 3.0;  // a "result": every copy must get its welded vertex's new position
  EXPECT_EQ(mesh_for_output(mesh, x).number_of_vertices(), static_cast<std::size_t>(m.x.rows()));
  for (const char* ext : {"off", "ply", "obj"}) {
    const std::string out = (dir_ / (std::string("out.") + ext)).string();
    write_mesh_atomic(out, mesh, x);
    std::vector<Point3> points;
    std::vector<std::vector<std::size_t>> polygons;
    SourceLines lines;
    read_polygon_soup(out, ext, points, polygons, lines);
    SCOPED_TRACE(ext);
    ASSERT_EQ(points.size(), static_cast<std::size_t>(m.x.rows()));
    for (std::size_t i = 0; i < points.size(); ++i)
      EXPECT_EQ(points[i], Point3(3.0 * m.x(static_cast<Eigen::Index>(i), 0), 3.0 * m.x(static_cast<Eigen::Index>(i), 1),
                                  3.0 * m.x(static_cast<Eigen::Index>(i), 2))) << i;
    ASSERT_EQ(polygons.size(), m.tris.size());
    for (std::size_t f = 0; f < polygons.size(); ++f)
      EXPECT_EQ(polygons[f], std::vector<std::size_t>(m.tris[f].begin(), m.tris[f].end())) << f;
  }
}

TEST_F(Seams, TheDocumentOfASplitFileStandsForTheWeldedMeshWithItsTextureCoordinates) {
  const SeamSplitMesh m = seam_split_sphere();
  for (const char* name : {"split.ply", "split.obj"}) {
    const std::string path = write(name, name[6] == 'p' ? m.ply() : m.obj());
    const Mesh mesh = read_input_mesh(path);
    const std::unique_ptr<MeshDocument> doc = read_mesh_document(path);
    SCOPED_TRACE(name);
    ASSERT_TRUE(doc && doc->matches(mesh));
    const CornerTexcoords t = doc->texcoords(mesh);
    ASSERT_EQ(t.face_uv.size(), m.tris.size());
    for (std::size_t f = 0; f < m.tris.size(); ++f)
      for (std::size_t k = 0; k < 3; ++k)
        for (std::size_t c = 0; c < 2; ++c)  // the file's s, t (text: all digits) of the corner's own copy
          EXPECT_EQ(t.uv[t.face_uv[f][k]][c], m.st[m.tris[f][k]][c]) << f << ' ' << k;
  }
}

}  // namespace
}  // namespace shellcontract
