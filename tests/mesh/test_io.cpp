// read_input_mesh / write_mesh_atomic / write_text_atomic / positions_from_mesh.
// Expected values are closed forms (unit cube volume 1), the generator's known counts
// (meshes/README.md), or an independent computation (the Eigen icosphere fixture).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <new>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/eigen_point_map.hpp"
#include "mesh/formats.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/mesh_fixtures.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

std::string mesh_path(const std::string& name) { return std::string(test::MESH_DIR) + "/" + name; }

std::array<std::size_t, 3> corners(const Mesh& mesh, std::size_t f) {
  std::array<std::size_t, 3> c{};
  int k = 0;
  for (const VertexIndex v : vertices_around_face(mesh.halfedge(FaceIndex(static_cast<Mesh::size_type>(f))), mesh))
    c[static_cast<std::size_t>(k++)] = v.idx();
  return c;
}

/// A fresh folder for one test, removed afterwards.
class TempDir {
 public:
  TempDir() {
    static int n = 0;
    path_ = fs::temp_directory_path() / ("shellcontract_test_io_" + std::to_string(::getpid()) + "_" + std::to_string(n++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  std::vector<std::string> entries() const {
    std::vector<std::string> e;
    for (const auto& d : fs::directory_iterator(path_)) e.push_back(d.path().filename().string());
    return e;
  }

 private:
  fs::path path_;
};

void write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// ----------------------------------------------------------------------------- good inputs

TEST(ReadInputMesh, UnitCubeKeepsFileOrderAndHasVolumeOne) {
  InputReport report;
  const Mesh mesh = read_input_mesh(mesh_path("cube.off"), &report);
  ASSERT_EQ(mesh.number_of_vertices(), 8u);
  ASSERT_EQ(mesh.number_of_faces(), 12u);
  EXPECT_EQ(report.vertices, 8u);
  EXPECT_EQ(report.faces, 12u);
  EXPECT_EQ(report.components, 1u);
  EXPECT_EQ(report.triangulated_faces, 0u);
  EXPECT_FALSE(report.reoriented);
  EXPECT_TRUE(report.zero_area_faces.empty());
  EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
  EXPECT_NEAR(report.volume, 1.0, 1e-14);
  // The file's vertices and faces, in file order (scripts/make_meshes.py CUBE_V / CUBE_QUADS,
  // each quad (a,b,c,d) split into (a,b,c), (a,c,d)). Corner order, first corner included.
  const double expected_v[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                   {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const std::size_t expected_f[12][3] = {{0, 3, 2}, {0, 2, 1}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                         {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  for (std::size_t i = 0; i < 8; ++i) {
    const Point3& p = mesh.point(VertexIndex(static_cast<Mesh::size_type>(i)));
    EXPECT_EQ(p.x(), expected_v[i][0]) << "vertex " << i;
    EXPECT_EQ(p.y(), expected_v[i][1]) << "vertex " << i;
    EXPECT_EQ(p.z(), expected_v[i][2]) << "vertex " << i;
  }
  for (std::size_t f = 0; f < 12; ++f) {
    const auto c = corners(mesh, f);
    EXPECT_EQ(c[0], expected_f[f][0]) << "face " << f;
    EXPECT_EQ(c[1], expected_f[f][1]) << "face " << f;
    EXPECT_EQ(c[2], expected_f[f][2]) << "face " << f;
  }
}

TEST(ReadInputMesh, IcosphereMatchesIndependentFixtureInOrder) {
  // meshes/ico2.off and test::icosphere(2, 0.5) use the same construction but were computed by
  // different programs (Python, Eigen): same order, positions equal to rounding.
  const test::TriMesh ref = test::icosphere(2, 0.5);
  InputReport report;
  const Mesh mesh = read_input_mesh(mesh_path("ico2.off"), &report);
  ASSERT_EQ(static_cast<Eigen::Index>(mesh.number_of_vertices()), ref.x.rows());
  ASSERT_EQ(static_cast<Eigen::Index>(mesh.number_of_faces()), ref.faces.rows());
  const Positions x = positions_from_mesh(mesh);
  EXPECT_LT((x - ref.x).cwiseAbs().maxCoeff(), 1e-15);
  for (Eigen::Index f = 0; f < ref.faces.rows(); ++f) {
    const auto c = corners(mesh, static_cast<std::size_t>(f));
    for (int k = 0; k < 3; ++k) ASSERT_EQ(c[static_cast<std::size_t>(k)], static_cast<std::size_t>(ref.faces(f, k))) << "face " << f;
  }
  EXPECT_NEAR(report.volume, test::signed_volume(ref.x, ref.faces), 1e-14);
  EXPECT_EQ(report.components, 1u);
}

TEST(ReadInputMesh, TorusHasEulerCharacteristicZero) {
  InputReport report;
  const Mesh mesh = read_input_mesh(mesh_path("torus.off"), &report);
  EXPECT_EQ(mesh.number_of_vertices(), 512u);  // 32 x 16 grid
  EXPECT_EQ(mesh.number_of_faces(), 1024u);
  const long long chi = static_cast<long long>(mesh.number_of_vertices()) - static_cast<long long>(mesh.number_of_edges()) +
                        static_cast<long long>(mesh.number_of_faces());
  EXPECT_EQ(chi, 0);
  EXPECT_EQ(report.components, 1u);
  EXPECT_GT(report.volume, 0.0);
  // Inscribed polyhedron: below the smooth torus 2 pi^2 R r^2 (R = 0.35, r = 0.15).
  EXPECT_LT(report.volume, 2.0 * M_PI * M_PI * 0.35 * 0.15 * 0.15);
}

TEST(ReadInputMesh, OctahedronVolumeIsFourThirds) {
  InputReport report;
  read_input_mesh(mesh_path("octahedron.off"), &report);
  EXPECT_NEAR(report.volume, 4.0 / 3.0, 1e-14);
}

TEST(ReadInputMesh, QuadsAreTriangulatedKeepingPolygonIndexFirst) {
  InputReport report;
  const Mesh mesh = read_input_mesh(mesh_path("cube_quads.off"), &report);
  ASSERT_EQ(mesh.number_of_faces(), 12u);
  EXPECT_EQ(report.triangulated_faces, 6u);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_EQ(report.warnings[0],
            "6 polygons with more than 3 vertices were split into 12 triangles (6 by a fan from a corner; the first triangle "
            "of each keeps the polygon's face index, the others are appended after face 5)");
  EXPECT_NEAR(report.volume, 1.0, 1e-14);
  // Quad i gives faces i and 6 + i (documented order); both use only the quad's corners, and
  // together they cover all four.
  const std::size_t quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  for (std::size_t q = 0; q < 6; ++q) {
    const std::set<std::size_t> quad(std::begin(quads[q]), std::end(quads[q]));
    std::set<std::size_t> covered;
    for (const std::size_t f : {q, 6 + q})
      for (const std::size_t v : corners(mesh, f)) {
        EXPECT_EQ(quad.count(v), 1u) << "face " << f << " uses vertex " << v << ", not a corner of quad " << q;
        covered.insert(v);
      }
    EXPECT_EQ(covered, quad) << "quad " << q;
  }
}

TEST(ReadInputMesh, InsideOutSphereIsFlippedWithWarning) {
  const test::TriMesh ref = test::icosphere(2, 0.5);
  InputReport report;
  const Mesh mesh = read_input_mesh(mesh_path("inside_out_sphere.off"), &report);
  EXPECT_TRUE(report.reoriented);
  ASSERT_FALSE(report.warnings.empty());
  EXPECT_NE(report.warnings[0].find("inside-out"), std::string::npos) << report.warnings[0];
  EXPECT_NEAR(report.volume, test::signed_volume(ref.x, ref.faces), 1e-14);
  // The file stores (a, c, b) for the fixture's (a, b, c); flipping swaps back, first corner kept.
  for (Eigen::Index f = 0; f < ref.faces.rows(); ++f) {
    const auto c = corners(mesh, static_cast<std::size_t>(f));
    for (int k = 0; k < 3; ++k) ASSERT_EQ(c[static_cast<std::size_t>(k)], static_cast<std::size_t>(ref.faces(f, k))) << "face " << f;
  }
}

TEST(ReadInputMesh, ZeroAreaFaceIsReportedNotRefused) {
  InputReport report;
  read_input_mesh(mesh_path("zero_area_face.off"), &report);
  EXPECT_EQ(report.zero_area_faces, std::vector<std::size_t>{13});
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("zero area"), std::string::npos) << report.warnings[0];
  EXPECT_NEAR(report.volume, 1.0, 1e-14);
}

TEST(ReadInputMesh, ComponentsAreCountedAndEachOrientedOnItsOwn) {
  // Two unit cubes, the second shifted by 3 in x and stored inside-out: 2 components, only the
  // second flipped, total volume 2.
  TempDir dir;
  std::ostringstream off;
  off << "OFF\n16 24 0\n";
  const int v[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int f[12][3] = {{0, 3, 2}, {0, 2, 1}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                        {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  for (int c = 0; c < 2; ++c)
    for (const auto& p : v) off << p[0] + 3 * c << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& t : f) off << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  for (const auto& t : f) off << "3 " << t[0] + 8 << ' ' << t[2] + 8 << ' ' << t[1] + 8 << '\n';
  write_file(dir.file("two_cubes.off"), off.str());
  InputReport report;
  read_input_mesh(dir.file("two_cubes.off"), &report);
  EXPECT_EQ(report.components, 2u);
  EXPECT_TRUE(report.reoriented);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("component 1"), std::string::npos) << report.warnings[0];
  EXPECT_NEAR(report.volume, 2.0, 1e-14);
}

TEST(ReadInputMesh, InsideOutFileGivesTheMeshOfTheOrientedFileHalfedgeForHalfedge) {
  // Edge and halfedge numbering orders the bending constraints, so a flipped input must not
  // only have the right faces but be the very mesh that the correctly oriented file gives.
  TempDir dir;
  const Mesh oriented = read_input_mesh(mesh_path("cube.off"));
  std::ostringstream off;
  off << std::setprecision(17) << "OFF\n" << oriented.number_of_vertices() << ' ' << oriented.number_of_faces() << " 0\n";
  for (const VertexIndex v : oriented.vertices()) off << oriented.point(v) << '\n';
  for (std::size_t f = 0; f < oriented.number_of_faces(); ++f) {
    const auto c = corners(oriented, f);
    off << "3 " << c[0] << ' ' << c[2] << ' ' << c[1] << '\n';  // inside-out, first corner kept
  }
  write_file(dir.file("flipped.off"), off.str());
  InputReport report;
  const Mesh flipped = read_input_mesh(dir.file("flipped.off"), &report);
  ASSERT_TRUE(report.reoriented);
  ASSERT_EQ(flipped.number_of_halfedges(), oriented.number_of_halfedges());
  for (const HalfedgeIndex h : oriented.halfedges()) {
    ASSERT_EQ(flipped.target(h), oriented.target(h)) << "halfedge " << h.idx();
    ASSERT_EQ(flipped.next(h), oriented.next(h)) << "halfedge " << h.idx();
    ASSERT_EQ(flipped.face(h), oriented.face(h)) << "halfedge " << h.idx();
  }
  for (const FaceIndex f : oriented.faces()) ASSERT_EQ(flipped.halfedge(f), oriented.halfedge(f)) << "face " << f.idx();
}

TEST(PositionsFromMesh, RowIsVertexIndex) {
  const Mesh mesh = read_input_mesh(mesh_path("ico1.off"));
  const Positions x = positions_from_mesh(mesh);
  ASSERT_EQ(static_cast<std::size_t>(x.rows()), mesh.number_of_vertices());
  for (const VertexIndex v : mesh.vertices()) {
    const Point3& p = mesh.point(v);
    EXPECT_EQ(x(v.idx(), 0), p.x());
    EXPECT_EQ(x(v.idx(), 1), p.y());
    EXPECT_EQ(x(v.idx(), 2), p.z());
  }
}

// ----------------------------------------------------------------------------- writing

/// ico2 with positions that need all 17 digits (irrational perturbations).
Positions awkward_positions(const Mesh& mesh) {
  Positions x = positions_from_mesh(mesh);
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    for (int k = 0; k < 3; ++k) x(i, k) *= 1.0 + 1e-3 * std::sin(std::sqrt(2.0) * static_cast<double>(3 * i + k));
  return x;
}

class RoundTrip : public ::testing::TestWithParam<std::string> {};

TEST_P(RoundTrip, KeepsOrderAndFullPrecision) {
  const Mesh mesh = read_input_mesh(mesh_path("ico2.off"));
  const Positions x = awkward_positions(mesh);
  // The perturbation really needs more than 15 digits somewhere, or the test could not fail.
  std::ostringstream s15;
  s15 << std::setprecision(15) << x(1, 0);
  ASSERT_NE(std::stod(s15.str()), x(1, 0));

  TempDir dir;
  const std::string path = dir.file("out." + GetParam());
  write_mesh_atomic(path, mesh, x);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out." + GetParam()}) << "temporary file left behind";
  const Mesh back = read_input_mesh(path);
  ASSERT_EQ(back.number_of_vertices(), mesh.number_of_vertices());
  ASSERT_EQ(back.number_of_faces(), mesh.number_of_faces());
  const Positions y = positions_from_mesh(back);
  if (!find_mesh_format(GetParam())->indexed_vertices) {
    // STL stores corner positions per face; readers number vertices by first appearance. The
    // face order and each face's corner positions (in order) must survive exactly.
    for (std::size_t f = 0; f < mesh.number_of_faces(); ++f) {
      const auto a = corners(mesh, f), b = corners(back, f);
      for (int k = 0; k < 3; ++k)
        ASSERT_EQ(Vec3(x.row(static_cast<Eigen::Index>(a[static_cast<std::size_t>(k)]))),
                  Vec3(y.row(static_cast<Eigen::Index>(b[static_cast<std::size_t>(k)]))))
            << "face " << f << " corner " << k;
    }
    return;
  }
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    for (int k = 0; k < 3; ++k) ASSERT_EQ(y(i, k), x(i, k)) << "vertex " << i << " coordinate " << k;  // bitwise
  for (std::size_t f = 0; f < mesh.number_of_faces(); ++f) ASSERT_EQ(corners(back, f), corners(mesh, f)) << "face " << f;
}

/// The formats write_mesh_atomic writes (formats.hpp), so that a new one is round-tripped too.
std::vector<std::string> plain_written_formats() {
  std::vector<std::string> out;
  for (const MeshFormat& f : MESH_FORMATS)
    if (f.plain_writer) out.push_back(f.ext);
  return out;
}

INSTANTIATE_TEST_SUITE_P(Formats, RoundTrip, ::testing::ValuesIn(plain_written_formats()));

TEST(WriteMeshAtomic, ReplacesAnExistingFileWhole) {
  TempDir dir;
  const std::string path = dir.file("m.off");
  write_file(path, "old content\n");
  const Mesh mesh = read_input_mesh(mesh_path("cube.off"));
  write_mesh_atomic(path, mesh, positions_from_mesh(mesh));
  const std::string text = read_file(path);
  EXPECT_EQ(text.rfind("OFF\n8 12 0\n", 0), 0u) << text;
  EXPECT_EQ(text.find("old content"), std::string::npos);
}

TEST(WriteMeshAtomic, FailureLeavesNoPartialFile) {
  TempDir dir;
  const Mesh mesh = read_input_mesh(mesh_path("cube.off"));
  const Positions x = positions_from_mesh(mesh);
  // Missing folder: nothing can be created.
  EXPECT_THROW(write_mesh_atomic(dir.file("no_such_folder/m.off"), mesh, x), UsageError);
  // The target is a folder: the temporary is written, the rename fails, the temporary must go.
  fs::create_directory(dir.file("taken.off"));
  try {
    write_mesh_atomic(dir.file("taken.off"), mesh, x);
    ADD_FAILURE() << "writing over a folder did not throw";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("taken.off"), std::string::npos) << e.what();
  }
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"taken.off"}) << "a temporary file was left behind";
  EXPECT_TRUE(fs::is_empty(dir.file("taken.off")));
  // Unknown extension: refused before anything is written.
  EXPECT_THROW(write_mesh_atomic(dir.file("m.xyz"), mesh, x), UsageError);
  EXPECT_FALSE(fs::exists(dir.file("m.xyz")));
  EXPECT_EQ(dir.entries().size(), 1u);
  // Wrong number of rows: a programming error, nothing written.
  EXPECT_THROW(write_mesh_atomic(dir.file("m.off"), mesh, Positions(x.topRows(7))), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir.file("m.off")));
}

TEST(WriteTextAtomic, WritesExactlyAndFailsCleanly) {
  TempDir dir;
  const std::string text = "a,b\n1,2\n";
  write_text_atomic(dir.file("log.csv"), text);
  EXPECT_EQ(read_file(dir.file("log.csv")), text);
  EXPECT_THROW(write_text_atomic(dir.file("missing/log.csv"), text), UsageError);
  fs::create_directory(dir.file("dir.csv"));
  EXPECT_THROW(write_text_atomic(dir.file("dir.csv"), text), UsageError);
  std::vector<std::string> e = dir.entries();
  std::sort(e.begin(), e.end());
  EXPECT_EQ(e, (std::vector<std::string>{"dir.csv", "log.csv"}));
}

TEST(WriteFileAtomic, StreamsTheFileAndAThrowingWriterLeavesTheOldOne) {
  // The .glb's writer: straight into the temporary file, so a writer that fails half-way (out
  // of memory) must leave the old file as it was and no temporary.
  TempDir dir;
  const std::string path = dir.file("a.glb");
  write_file(path, "old content\n");
  EXPECT_THROW(write_file_atomic(path,
                                 [](std::ostream& out) {
                                   out << "half a file";
                                   throw std::bad_alloc();
                                 }),
               std::bad_alloc);
  EXPECT_EQ(read_file(path), "old content\n");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"a.glb"}) << "a temporary file was left behind";
  write_file_atomic(path, [](std::ostream& out) { out.write("glTF\0\x02", 6); });
  EXPECT_EQ(read_file(path), std::string("glTF\0\x02", 6));
  EXPECT_THROW(write_file_atomic(dir.file("missing/a.glb"), [](std::ostream&) {}), UsageError);
}

// ----------------------------------------------------------------------------- bad inputs

struct BadCase {
  const char* file;                        ///< under meshes/bad/
  std::vector<std::string> must_contain;   ///< problem name, then where
};

void PrintTo(const BadCase& c, std::ostream* os) { *os << c.file; }

class BadInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadInput, ThrowsInputErrorNamingFileProblemAndPlace) {
  const BadCase& c = GetParam();
  const std::string path = std::string(test::MESH_DIR) + "/bad/" + c.file;
  try {
    read_input_mesh(path);
    FAIL() << c.file << " was accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << "message does not name the file: " << msg;
    for (const std::string& s : c.must_contain) EXPECT_NE(msg.find(s), std::string::npos) << "missing '" << s << "' in: " << msg;
  }
}

// Places follow meshes/README.md (bad/ table) and the files' construction in make_meshes.py.
INSTANTIATE_TEST_SUITE_P(
    Files, BadInput,
    ::testing::Values(
        BadCase{"empty.off", {"empty file"}},
        BadCase{"truncated.off", {"truncated file", "12 faces", "face 5 (line 16)"}},
        BadCase{"garbage.off", {"parse error", "line 1", "OFF header"}},
        BadCase{"nan.off", {"non-finite coordinate", "vertex 3 (line 6)", "nan"}},
        BadCase{"index_out_of_range.off", {"vertex index out of range", "face 4 (line 15)", "vertex 8", "8 vertices"}},
        BadCase{"repeated_vertex.off", {"degenerate face", "face 7 (line 18)", "vertex 1 twice"}},
        BadCase{"duplicate_face.off", {"duplicate face", "face 12 (line 23)", "face 2 (line 13)"}},
        BadCase{"open_sheet.off", {"open boundary", "edge (", "face 0", "vertex 0"}},
        BadCase{"nonmanifold_edge.off", {"non-manifold edge", "edge (0, 1)", "4 faces"}},
        BadCase{"nonmanifold_vertex.off", {"non-manifold vertex", "vertex 0 (line 4)", "several fans"}},
        BadCase{"inconsistent_orientation.off", {"inconsistent orientation", "face 2 (line 13)", "face 5 (line 16)", "edge (4, 5)"}},
        BadCase{"cube.xyz", {"unknown extension", ".xyz"}},
        BadCase{"no_such_file.off", {"cannot open file", "no such file"}}));

TEST(BadInputOtherFormats, ObjIndexOutOfRangeAndOpenStl) {
  TempDir dir;
  // OBJ counts from 1: "f 1 2 9" refers to vertex 8 (0-based) of 4.
  write_file(dir.file("oor.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 9\n");
  try {
    read_input_mesh(dir.file("oor.obj"));
    FAIL() << "accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    // Either CGAL refuses the index while parsing, or our soup check names it.
    EXPECT_TRUE(msg.find("vertex index out of range") != std::string::npos || msg.find("parse error") != std::string::npos) << msg;
  }
  // One STL triangle: an open surface.
  write_file(dir.file("one.stl"), "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n");
  try {
    read_input_mesh(dir.file("one.stl"));
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("open boundary"), std::string::npos) << e.what();
  }
}

TEST(BadInputOtherFormats, TruncatedPlyIsATruncatedFile) {
  TempDir dir;
  write_file(dir.file("t.ply"), "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
                                "element face 4\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n");
  try {
    read_input_mesh(dir.file("t.ply"));
    FAIL() << "accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    // The 4 vertices and 4 faces the header declares cannot fit in the 12 bytes after it.
    EXPECT_NE(msg.find("truncated file"), std::string::npos) << msg;
    EXPECT_NE(msg.find("4 'vertex' elements (line 3)"), std::string::npos) << msg;
  }
}

// Before: a folder whose name has no known extension was "unknown extension: '.'"; it is named as
// a folder, as a folder named like a mesh (x.off) is.
TEST(BadInputOtherFormats, AFolderIsNamedAsAFolderWhateverItsName) {
  TempDir dir;
  for (const std::string name : {"plain", "meshes.d", "x.off"}) {
    fs::create_directory(dir.file(name));
    try {
      read_input_mesh(dir.file(name));
      FAIL() << name << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("it is a folder"), std::string::npos) << name << ": " << e.what();
    }
  }
}

// Before: a file whose name has no extension was "unknown extension: '.'", an extension it does not
// have; now it is said to have none, with the ones that are read.
TEST(BadInputOtherFormats, AFileWithoutExtensionIsSaidToHaveNone) {
  TempDir dir;
  for (const std::string name : {"plain", "trailing."}) {
    write_file(dir.file(name), "OFF\n");
    try {
      read_input_mesh(dir.file(name));
      FAIL() << name << " accepted";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(
          msg.find(
              ": the file name has no extension: expected .off, .obj, .ply, .stl, .glb or .gltf"),
          std::string::npos)
          << name << ": " << msg;
      EXPECT_EQ(msg.find("'.'"), std::string::npos) << name << ": " << msg;
    }
  }
}

}  // namespace
}  // namespace shellcontract
