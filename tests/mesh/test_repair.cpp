// repair_input_mesh (docs/design/repair.md): each defect CGAL's repair steps address, on the unit
// cube (volume 1, 8 vertices, 12 faces) made defective in one known way.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "core/progress_stage.hpp"
#include "mesh/eigen_point_map.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/repair.hpp"
#include "shellcontract/validation.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

const std::vector<std::array<double, 3>> CUBE_POINTS = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                                        {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
/// Outward-oriented (counter-clockwise seen from outside), as meshes/cube.off.
const std::vector<std::array<int, 3>> CUBE_FACES = {{0, 3, 2}, {0, 2, 1}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                                    {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};

class Repair : public ::testing::Test {
 protected:
  fs::path dir;
  void SetUp() override {
    dir = fs::temp_directory_path() / ("shellcontract_repair_" + std::to_string(::getpid()) + "_" +
                                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }

  std::string write_off(const std::string& name, const std::vector<std::array<double, 3>>& pts,
                        const std::vector<std::array<int, 3>>& faces) {
    const std::string path = (dir / name).string();
    std::ofstream f(path);
    f << "OFF\n" << pts.size() << ' ' << faces.size() << " 0\n";
    for (const auto& p : pts) f << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    for (const auto& t : faces) f << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    return path;
  }
};

double volume_of(const Mesh& mesh) { return enclosed_volume(mesh, positions_from_mesh(mesh)); }

/// Every face's normal points away from the cube's centre: consistently and outward oriented.
void expect_outward(const Mesh& mesh) {
  const Vec3 centre(0.5, 0.5, 0.5);
  for (const FaceIndex f : mesh.faces()) {
    std::vector<Vec3> p;
    for (const VertexIndex v : mesh.vertices_around_face(mesh.halfedge(f)))
      p.emplace_back(mesh.point(v).x(), mesh.point(v).y(), mesh.point(v).z());
    const Vec3 n = (p[1] - p[0]).cross(p[2] - p[0]);
    EXPECT_GT(n.dot((p[0] + p[1] + p[2]) / 3.0 - centre), 0.0) << "face " << f.idx() << " points inward";
  }
}

TEST_F(Repair, ARepairNamesItsStagesInOrder) {
  // `shellcontract repair` names the stage it is in when one lasts (core/progress_stage.hpp).
  const std::vector<std::array<int, 3>> faces(CUBE_FACES.begin() + 2, CUBE_FACES.end());
  const std::string path = write_off("open_cube.off", CUBE_POINTS, faces);
  std::vector<std::string> stages;
  const ProgressStageScope scope([&](const std::string& s) { stages.push_back(s); });
  repair_input_mesh(path);
  const std::vector<std::string> expected = {
      "reading " + path,
      "checking " + path,
      "reading " + path + " as polygons to repair",
      "repairing the polygons (duplicates, degenerate faces, orientation)",
      "stitching the borders",
      "filling 1 hole",
      "checking the fills for self-intersections",
      "dropping open components, orienting",
      "checking the repaired mesh"};
  EXPECT_EQ(stages, expected);
}

TEST_F(Repair, UsableMeshIsReturnedUnchanged) {
  const std::string path = write_off("cube.off", CUBE_POINTS, CUBE_FACES);
  RepairReport r;
  const Mesh m = repair_input_mesh(path, &r);
  EXPECT_TRUE(r.already_usable);
  EXPECT_TRUE(r.usable);
  const Mesh read = read_input_mesh(path);
  ASSERT_EQ(m.number_of_vertices(), read.number_of_vertices());
  EXPECT_TRUE(positions_from_mesh(m) == positions_from_mesh(read));
}

TEST_F(Repair, CubeWithOneFaceRemovedGetsOneHoleFilledAndItsVolumeBack) {
  // The two triangles of the bottom square (z = 0) are removed: one square hole of 4 edges.
  const std::vector<std::array<int, 3>> faces(CUBE_FACES.begin() + 2, CUBE_FACES.end());
  const std::string path = write_off("open_cube.off", CUBE_POINTS, faces);
  EXPECT_THROW(read_input_mesh(path), InputError);
  RepairReport r;
  const Mesh m = repair_input_mesh(path, &r);
  EXPECT_FALSE(r.already_usable);
  EXPECT_NE(r.input_problem.find("open boundary"), std::string::npos) << r.input_problem;
  EXPECT_EQ(r.holes_filled, 1u);
  EXPECT_EQ(r.largest_hole_edges, 4u);
  EXPECT_EQ(r.holes_unfilled, 0u);
  EXPECT_EQ(r.components_dropped, 0u);
  EXPECT_EQ(m.number_of_faces(), 10u + r.hole_faces_added);
  EXPECT_TRUE(CGAL::is_closed(m));
  // The hole is a planar square: any fill in its plane restores the cube; fairing could only
  // bulge it if refinement added inner vertices, which a 4-edge hole of this size does not get.
  EXPECT_EQ(r.hole_vertices_added, 0u);
  EXPECT_EQ(r.hole_self_intersections, 0u);  // a fill in the square's plane touches only its edges
  EXPECT_NEAR(volume_of(m), 1.0, 1e-12);
  expect_outward(m);
}

TEST_F(Repair, FlippedFaceIsReoriented) {
  std::vector<std::array<int, 3>> faces = CUBE_FACES;
  std::swap(faces[6][1], faces[6][2]);
  const std::string path = write_off("flipped.off", CUBE_POINTS, faces);
  RepairReport r;
  const Mesh m = repair_input_mesh(path, &r);
  EXPECT_NE(r.input_problem.find("inconsistent orientation"), std::string::npos) << r.input_problem;
  EXPECT_EQ(m.number_of_faces(), 12u);
  EXPECT_EQ(m.number_of_vertices(), 8u);
  EXPECT_EQ(r.holes_filled, 0u);
  EXPECT_NEAR(volume_of(m), 1.0, 1e-12);
  expect_outward(m);
}

TEST_F(Repair, InsideOutOpenCubeIsFilledAndTurnedOutward) {
  std::vector<std::array<int, 3>> faces(CUBE_FACES.begin() + 2, CUBE_FACES.end());
  for (auto& t : faces) std::swap(t[1], t[2]);
  const Mesh m = repair_input_mesh(write_off("inside_out_open.off", CUBE_POINTS, faces));
  EXPECT_NEAR(volume_of(m), 1.0, 1e-12);
  expect_outward(m);
}

TEST_F(Repair, DuplicatedVerticesAreStitched) {
  // A triangle soup as STL stores it: each face has its own three points (36 points). Welded
  // at its identical positions it is the cube, which read_input_mesh does itself (seams,
  // mesh_io.hpp); with one facet repeated, welding gives a duplicate face and repair is needed.
  std::vector<std::array<double, 3>> pts;
  std::vector<std::array<int, 3>> faces;
  for (const auto& t : CUBE_FACES) {
    const int base = static_cast<int>(pts.size());
    for (int k = 0; k < 3; ++k) pts.push_back(CUBE_POINTS[t[k]]);
    faces.push_back({base, base + 1, base + 2});
  }
  RepairReport as_read;
  EXPECT_EQ(repair_input_mesh(write_off("soup.off", pts, faces), &as_read).number_of_vertices(), 8u);
  EXPECT_TRUE(as_read.already_usable);
  EXPECT_EQ(as_read.input_report.welded_vertices, 36u - 8u);
  for (int k = 0; k < 3; ++k) pts.push_back(pts[static_cast<std::size_t>(k)]);
  faces.push_back({36, 37, 38});
  const std::string path = write_off("repeated.off", pts, faces);
  RepairReport r;
  const Mesh m = repair_input_mesh(path, &r);
  EXPECT_FALSE(r.already_usable);
  EXPECT_EQ(r.duplicate_points_merged, 39u - 8u);
  EXPECT_EQ(m.number_of_vertices(), 8u);
  EXPECT_EQ(m.number_of_faces(), 12u);
  EXPECT_EQ(r.holes_filled, 0u);
  EXPECT_NEAR(volume_of(m), 1.0, 1e-12);
}

TEST_F(Repair, StrayTriangleComponentIsDroppedAndCubeKept) {
  std::vector<std::array<double, 3>> pts = CUBE_POINTS;
  pts.push_back({3, 0, 0});
  pts.push_back({4, 0, 0});
  pts.push_back({3, 1, 0});
  std::vector<std::array<int, 3>> faces = CUBE_FACES;
  faces.push_back({8, 9, 10});
  RepairReport r;
  const Mesh m = repair_input_mesh(write_off("stray.off", pts, faces), &r);
  // The triangle's hole is filled by its own mirror: a closed component with zero volume.
  EXPECT_EQ(r.components_dropped, 1u);
  EXPECT_EQ(m.number_of_faces(), 12u);
  EXPECT_EQ(m.number_of_vertices(), 8u);
  EXPECT_NEAR(volume_of(m), 1.0, 1e-12);
}

TEST_F(Repair, SingleTriangleCannotBeRepairedAndTheMessageSaysWhy) {
  const std::string path = write_off("triangle.off", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
  RepairReport r;
  try {
    repair_input_mesh(path, &r);
    FAIL() << "a single triangle was repaired";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(path + ": cannot repair: ", 0), 0u) << msg;
    EXPECT_NE(msg.find("no component encloses a volume"), std::string::npos) << msg;
  }
  EXPECT_FALSE(r.usable);
  EXPECT_FALSE(r.failure.empty());
}

TEST_F(Repair, PointCloudCannotBeRepaired) {
  const std::string path = write_off("points.off", CUBE_POINTS, {});
  try {
    repair_input_mesh(path);
    FAIL() << "a point set was repaired";
  } catch (const InputError& e) {
    // The reader already refuses an OFF file without faces; repair passes its reason on.
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(path + ": cannot repair: ", 0), 0u) << msg;
    EXPECT_NE(msg.find("0 faces"), std::string::npos) << msg;
  }
}

// Repair merges, splits and adds vertices but moves none of the input's (a hole's fill moves only
// its own new vertices): those come back with their input coordinates, bit for bit. Before, every
// coordinate went through (x - c) / d * d + c, which changes the last bits of many.
TEST_F(Repair, VerticesRepairDoesNotMoveKeepTheirExactCoordinates) {
  std::vector<std::array<double, 3>> pts;
  // A box some of whose coordinates the old round trip changed in their last bits.
  for (const auto& p : CUBE_POINTS)
    pts.push_back({p[0] * 0.29 + 0.17, p[1] * 0.71 + 0.23, p[2] * 1.13 + 0.31});
  const std::string path = (dir / "open_cube.off").string();
  {
    std::ofstream f(path);
    f << std::setprecision(17) << "OFF\n8 10 0\n";
    for (const auto& p : pts) f << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    for (std::size_t t = 2; t < CUBE_FACES.size(); ++t)
      f << "3 " << CUBE_FACES[t][0] << ' ' << CUBE_FACES[t][1] << ' ' << CUBE_FACES[t][2] << '\n';
  }
  RepairReport r;
  const Mesh m = repair_input_mesh(path, &r);
  ASSERT_EQ(r.holes_filled, 1u);
  ASSERT_EQ(r.hole_vertices_added, 0u);
  ASSERT_EQ(m.number_of_vertices(), 8u);
  std::size_t exact = 0;
  for (const VertexIndex v : m.vertices()) {
    const Point3& q = m.point(v);
    for (const auto& p : pts) exact += q.x() == p[0] && q.y() == p[1] && q.z() == p[2];
  }
  EXPECT_EQ(exact, 8u);
}

}  // namespace
}  // namespace shellcontract
