// enclosed_volume: closed forms (unit cube 1, octahedron 4/3, scaling by s gives s^3), sign
// convention, refusal of open meshes, and that the positions argument (not the mesh's own
// points) is what gets measured.
#include <gtest/gtest.h>

#include <string>

#include "mesh/eigen_point_map.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/validation.hpp"
#include "support/cgal_mesh.hpp"
#include "support/mesh_fixtures.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

std::string mesh_path(const std::string& name) { return std::string(test::MESH_DIR) + "/" + name; }

/// Unit cube [0,1]^3 as an Eigen fixture; `outward` false reverses every face.
test::TriMesh unit_cube(bool outward) {
  test::TriMesh m;
  m.x.resize(8, 3);
  m.x << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1;
  m.faces.resize(12, 3);
  m.faces << 0, 3, 2, 0, 2, 1, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7;
  if (!outward) m.faces.col(1).swap(m.faces.col(2));
  return m;
}

TEST(EnclosedVolume, UnitCubeIsOne) {
  const Mesh mesh = read_input_mesh(mesh_path("cube.off"));
  EXPECT_NEAR(enclosed_volume(mesh, positions_from_mesh(mesh)), 1.0, 1e-15);
}

TEST(EnclosedVolume, OctahedronIsFourThirds) {
  const Mesh mesh = read_input_mesh(mesh_path("octahedron.off"));
  EXPECT_NEAR(enclosed_volume(mesh, positions_from_mesh(mesh)), 4.0 / 3.0, 1e-15);
}

TEST(EnclosedVolume, FlippedOrientationIsNegative) {
  // Built directly (read_input_mesh would reorient it).
  const Mesh inward = test::to_surface_mesh(unit_cube(false));
  EXPECT_NEAR(enclosed_volume(inward, positions_from_mesh(inward)), -1.0, 1e-15);
}

TEST(EnclosedVolume, ReadingReorientsAnInsideOutSphere) {
  // The flipped file measured as stored is negative; read_input_mesh makes it positive.
  const test::TriMesh ref = test::icosphere(2, 0.5);
  const double v_ref = test::signed_volume(ref.x, ref.faces);
  ASSERT_GT(v_ref, 0.0);
  const Mesh mesh = read_input_mesh(mesh_path("inside_out_sphere.off"));
  EXPECT_NEAR(enclosed_volume(mesh, positions_from_mesh(mesh)), v_ref, 1e-14);
}

TEST(EnclosedVolume, DeformedPositionsAreMeasuredNotTheMeshPoints) {
  // CGAL ignores a misnamed named parameter without a word, so check that x is really used:
  // scaling by 2 gives 8, translating keeps 1, while the mesh's own points stay the unit cube.
  const Mesh mesh = read_input_mesh(mesh_path("cube.off"));
  const Positions rest = positions_from_mesh(mesh);
  const double v_rest = enclosed_volume(mesh, rest);
  const Positions scaled = 2.0 * rest;
  const double v_scaled = enclosed_volume(mesh, scaled);
  EXPECT_NEAR(v_rest, 1.0, 1e-15);
  EXPECT_NEAR(v_scaled, 8.0, 1e-14);
  Positions moved = rest;
  moved.rowwise() += Eigen::RowVector3d(10.0, -3.0, 7.0);
  EXPECT_NEAR(enclosed_volume(mesh, moved), 1.0, 1e-13);
  // Only vertex 6 = (1,1,1) pushed out to (2,1,1): the top and side faces through it tilt.
  // Cube with one corner moved along x by 1: volume 1 + the added slab measured by the
  // divergence sum of the fixture (independent code path).
  Positions corner = rest;
  corner(6, 0) = 2.0;
  const test::TriMesh cube = unit_cube(true);
  EXPECT_NEAR(enclosed_volume(mesh, corner), test::signed_volume(corner, cube.faces), 1e-14);
  EXPECT_GT(enclosed_volume(mesh, corner), 1.0 + 1e-3);
  // The unchecked variant the simulator uses every frame measures the same positions.
  EXPECT_NEAR(enclosed_volume_unchecked(mesh, corner), test::signed_volume(corner, cube.faces), 1e-14);
  EXPECT_NEAR(enclosed_volume_unchecked(mesh, scaled), 8.0, 1e-14);
  EXPECT_THROW(enclosed_volume_unchecked(mesh, Positions(rest.topRows(7))), std::invalid_argument);
}

TEST(EnclosedVolume, OpenSheetIsReportedAsNotClosed) {
  // 2 x 2 grid square at z = 0: 9 vertices, 8 triangles, 8 border edges.
  test::TriMesh sheet;
  sheet.x.resize(9, 3);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) sheet.x.row(3 * j + i) << 0.5 * i, 0.5 * j, 0.0;
  sheet.faces.resize(8, 3);
  int f = 0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int a = 3 * j + i;
      sheet.faces.row(f++) << a, a + 1, a + 4;
      sheet.faces.row(f++) << a, a + 4, a + 3;
    }
  const Mesh mesh = test::to_surface_mesh(sheet);
  try {
    enclosed_volume(mesh, positions_from_mesh(mesh));
    FAIL() << "an open sheet got a volume";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("not closed"), std::string::npos) << msg;
    EXPECT_NE(msg.find("8 border edges"), std::string::npos) << msg;
  }
}

TEST(EnclosedVolume, WrongRowCountIsRefused) {
  const Mesh mesh = read_input_mesh(mesh_path("cube.off"));
  const Positions x = positions_from_mesh(mesh);
  EXPECT_THROW(enclosed_volume(mesh, Positions(x.topRows(7))), std::invalid_argument);
}

}  // namespace
}  // namespace shellcontract
