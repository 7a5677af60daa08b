// Per-vertex output fields (issue "materials and regions", item 6): known values on a sphere.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: temporary files of this process's own

#include <filesystem>

#include "shellcontract/mesh_io.hpp"
#include "sim/fields.hpp"
#include "support/cgal_mesh.hpp"

namespace shellcontract {
namespace {

TEST(Fields, SphereAtRestHasKnownCurvaturePressureAndNoEnergy) {
  SimOptions opt;
  opt.pressure = 3.0;
  opt.collisions = false;
  Simulator sim(test::to_surface_mesh(test::icosphere(3, 1.0)), opt);
  const VertexFields f = compute_vertex_fields(sim);
  // Normalized: the unit sphere's bounding-box diagonal 2 sqrt(3) becomes 1, so r = 1/(2 sqrt 3).
  const double r = 1.0 / (2.0 * std::sqrt(3.0));
  for (Eigen::Index i = 0; i < f.mean_curvature.size(); ++i) {
    EXPECT_NEAR(f.mean_curvature(i) * r, 1.0, 0.02) << i;
    EXPECT_NEAR(f.gaussian_curvature(i) * r * r, 1.0, 0.02) << i;
    EXPECT_NEAR(f.pressure(i) / 3.0, 1.0, 0.01) << i;  // |f| per area = P on a smooth sphere
    EXPECT_LE(f.energy_density(i), 1e-20) << i;
  }
  sim.step();
  sim.step();
  EXPECT_GT(compute_vertex_fields(sim).energy_density.maxCoeff(), 0.0) << "deformed: elastic energy";
}

TEST(Fields, ColourMapEndpointsAndPlyRoundTrip) {
  EXPECT_EQ(field_colour(0.0), Eigen::Vector3i(0, 0, 255));
  EXPECT_EQ(field_colour(0.5), Eigen::Vector3i(255, 255, 255));
  EXPECT_EQ(field_colour(1.0), Eigen::Vector3i(255, 0, 0));
  EXPECT_EQ(field_colour(-3.0), field_colour(0.0));
  EXPECT_EQ(field_colour(7.0), field_colour(1.0));
  SimOptions opt;
  opt.collisions = false;
  Simulator sim(test::to_surface_mesh(test::icosphere(2, 2.0)), opt);
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("shellcontract_fields_" + std::to_string(::getpid()) + ".ply"))
                               .string();
  write_fields_ply(path, sim, sim.positions_in_input_units(), compute_vertex_fields(sim), FieldColour::Pressure);
  const Mesh back = read_input_mesh(path);
  std::filesystem::remove(path);
  ASSERT_EQ(back.number_of_vertices(), static_cast<std::size_t>(sim.positions().rows()));
  const Positions x = sim.positions_in_input_units();
  for (VertexIndex v : back.vertices())
    EXPECT_NEAR(back.point(v).x(), x(v.idx(), 0), 1e-12 * 2.0);
}

}  // namespace
}  // namespace shellcontract
