// Per-vertex output fields (issue "materials and regions", item 6): known values on a sphere.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: temporary files of this process's own

#include <algorithm>
#include <filesystem>
#include <vector>

#include "shellcontract/mesh_io.hpp"
#include "sim/fields.hpp"
#include "sim/simulator_state.hpp"
#include "support/cgal_mesh.hpp"

namespace shellcontract {
namespace {

TEST(Fields, SphereAtRestHasKnownCurvaturePressureAndNoEnergy) {
  SimOptions opt;
  opt.pressure = 3.0;
  opt.collisions = false;
  Simulator sim(test::to_surface_mesh(test::icosphere(3, 1.0)), opt);
  const VertexFields f = compute_vertex_fields(sim);
  // The curvatures in the input's units, as `regions -o` writes them: the unit sphere's 1/r = 1
  // (not the normalized sphere's 2 sqrt 3, whose diagonal is 1).
  for (Eigen::Index i = 0; i < f.mean_curvature.size(); ++i) {
    EXPECT_NEAR(f.mean_curvature(i), 1.0, 0.02) << i;
    EXPECT_NEAR(f.gaussian_curvature(i), 1.0, 0.02) << i;
    EXPECT_NEAR(f.pressure(i) / 3.0, 1.0, 0.01) << i;  // force per area = P on a smooth sphere
    EXPECT_LE(f.energy_density(i), 1e-20) << i;
  }
  sim.step();
  sim.step();
  EXPECT_GT(compute_vertex_fields(sim).energy_density.maxCoeff(), 0.0) << "deformed: elastic energy";
}

/// The median of a field (the fields of a sphere vary by the mesh's small irregularity only).
double median(const Eigen::VectorXd& v) {
  std::vector<double> s(v.data(), v.data() + v.size());
  std::nth_element(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(s.size() / 2), s.end());
  return s[s.size() / 2];
}

/// The fields of a sphere of radius r in the file's units, its state shrunk by `s` about its
/// centre (V/V0 = s^3) at `frame`.
VertexFields shrunk_sphere(const SimOptions& opt, double r, double s, int frame) {
  Simulator sim(test::to_surface_mesh(test::icosphere(3, r)), opt);
  SimulatorState st = sim.state();
  const Eigen::RowVector3d c = st.x.colwise().mean();
  st.x = ((st.x.rowwise() - c) * s).rowwise() + c;
  st.frame = frame;
  sim.restore(st);
  return compute_vertex_fields(sim);
}

TEST(Fields, PressureIsTheNetLoadOfTheEnclosedAirAtTheState) {
  SimOptions opt;
  opt.pressure = 3.0;
  opt.air_balance = 0.5;
  opt.collisions = false;
  const double s = 0.8, v = s * s * s;
  // docs/math/air-pressure.md section 1: p_out = P / (1 - R), net p_out (1 - R / v).
  const double expected = opt.pressure / (1.0 - opt.air_balance) * (1.0 - opt.air_balance / v);
  const VertexFields f = shrunk_sphere(opt, 0.5, s, 0);
  EXPECT_NEAR(median(f.pressure), expected, 0.01 * expected);
  // The curvature of the shrunk sphere in the file's units: 1 / (0.8 * 0.5).
  EXPECT_NEAR(median(f.mean_curvature), 1.0 / (s * 0.5), 0.02 / (s * 0.5));
}

TEST(Fields, PressureFollowsTheKeysAndKeepsItsSign) {
  SimOptions opt;
  opt.collisions = false;
  opt.air_balance = 0.0;
  opt.pressure = 4.0;  // the keys' largest, as resolve_run_options sets it
  opt.pressure_schedule = Schedule({{0, 4.0}, {10, 0.0}});
  EXPECT_NEAR(median(shrunk_sphere(opt, 1.0, 1.0, 0).pressure), 4.0, 0.04);
  const VertexFields end = shrunk_sphere(opt, 1.0, 1.0, 10);
  EXPECT_EQ(end.pressure.cwiseAbs().maxCoeff(), 0.0) << "the keyed pressure is 0 at frame 10";
  // An inflating pressure (-p -2) pushes outward: a negative field.
  SimOptions inflate;
  inflate.collisions = false;
  inflate.pressure = -2.0;
  const VertexFields f = shrunk_sphere(inflate, 1.0, 1.0, 0);
  EXPECT_NEAR(median(f.pressure), -2.0, 0.02);
  EXPECT_LT(f.pressure.maxCoeff(), 0.0);
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
