// The regions' PLY (src/geometry/region_ply.cpp), formatted in parallel chunks: byte for byte
// the file CGAL's PLY writer gives (write_ply_atomic) for mesh_for_output's copy with the colour
// and region maps attached and, when the mesh has them, the curvature maps, built here. On an
// icosphere with more vertices and faces than a chunk holds, at positions that are not the
// mesh's points (with a -0 and negative curvature), with and without the curvature maps.
// Checked to fail when a face lists its corners from the source of its halfedge instead of the
// target.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: one temporary folder per test process

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <CGAL/IO/Color.h>

#include "geometry/curvature.hpp"
#include "mesh/properties.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/regions.hpp"
#include "support/cgal_mesh.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

std::string temp_path(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("shellcontract_test_region_ply_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// The file as CGAL writes it: the copy at x, colour and id per face, then the curvature maps.
std::string cgal_region_ply(const Mesh& mesh, const Positions& x, const std::string& path) {
  const std::vector<int> region = stored_regions(mesh);
  Mesh out = mesh_for_output(mesh, x);
  auto colour = property::add_map<FaceIndex, CGAL::IO::Color>(out, property::FACE_COLOR);
  auto id = property::add_map<FaceIndex, int>(out, property::REGION, -1);
  for (FaceIndex f : out.faces()) {
    const auto rgb = region_colour(region[f.idx()]);
    colour[f] = CGAL::IO::Color(rgb[0], rgb[1], rgb[2]);
    id[f] = region[f.idx()];
  }
  const auto [H_in, has_H] = mesh.property_map<VertexIndex, double>(property::MEAN_CURVATURE);
  const auto [K_in, has_K] = mesh.property_map<VertexIndex, double>(property::GAUSSIAN_CURVATURE);
  if (has_H && has_K) {
    auto H = property::add_map<VertexIndex, double>(out, property::MEAN_CURVATURE);
    auto K = property::add_map<VertexIndex, double>(out, property::GAUSSIAN_CURVATURE);
    for (VertexIndex v : out.vertices()) H[v] = H_in[v], K[v] = K_in[v];
  }
  write_ply_atomic(path, out, "shellcontract regions: face colour = region, grey = none");
  return slurp(path);
}

TEST(RegionPly, SameBytesAsCgalsWriterWithAndWithoutCurvature) {
  const test::TriMesh m = test::icosphere(5);  // 10242 vertices, 20480 faces: several chunks
  Mesh mesh = test::to_surface_mesh(m);
  Positions x = m.x;
  for (Eigen::Index i = 0; i < x.rows(); ++i) x.row(i) *= 1.0 + 0.3 * std::sin(5.0 * x(i, 0)) * std::cos(3.0 * x(i, 1));
  x(0, 0) = -0.0;
  x(1, 2) = 1e-300;
  std::vector<int> region(mesh.number_of_faces());
  for (std::size_t f = 0; f < region.size(); ++f) region[f] = static_cast<int>(f % 13) - 1;  // -1 and 0..11
  store_regions(mesh, region);
  const Mesh plain = mesh;
  store_curvature(mesh, compute_curvature(mesh, x));
  for (const Mesh* input : {static_cast<const Mesh*>(&mesh), &plain}) {
    const std::string ours = temp_path("ours.ply"), theirs = temp_path("cgal.ply");
    write_region_ply(ours, *input, x);
    const std::string expected = cgal_region_ply(*input, x, theirs);
    const std::string got = slurp(ours);
    ASSERT_FALSE(expected.empty());
    EXPECT_EQ(expected.find("property double mean_curvature") != std::string::npos, input == &mesh);
    EXPECT_EQ(got.size(), expected.size());
    EXPECT_TRUE(got == expected) << "first difference at byte "
                                 << std::distance(got.begin(), std::mismatch(got.begin(), got.end(), expected.begin(),
                                                                             expected.end()).first);
  }
}

TEST(RegionPly, APositionThatIsNotFiniteIsRefusedAndNothingIsWritten) {
  // Before: "nan 0 0" was written, a file that `check` then refuses.
  const test::TriMesh m = test::icosphere(1);
  Mesh mesh = test::to_surface_mesh(m);
  store_regions(mesh, std::vector<int>(mesh.number_of_faces(), -1));
  for (const double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL}) {
    Positions x = m.x;
    x(3, 1) = bad;
    const std::string path = temp_path("not_finite.ply");
    fs::remove(path);
    try {
      write_region_ply(path, mesh, x);
      ADD_FAILURE() << "written with " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("vertex 3 has a coordinate that is not finite"),
                std::string::npos)
          << e.what();
    }
    EXPECT_FALSE(fs::exists(path));
  }
}

}  // namespace
}  // namespace shellcontract
