// Runs of the default options (issue "Control", item 5) and of the local contraction (issue
// "Local contraction", items 1-2), shared by the default-suite subset (tests/scenario) and the
// long runs (tests/long).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <map>
#include <utility>

#include "mesh/eigen_point_map.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/run.hpp"
#include "sim/rest_state.hpp"
#include "support/cgal_mesh.hpp"
#include "support/mesh_fixtures.hpp"
#include "support/target_volume_case.hpp"
#include "test_paths.hpp"

namespace shellcontract::test {

/// A mesh of CGAL's demo data that scripts/fetch_paper_meshes.sh extracts beside the paper's.
inline std::string demo_mesh_path(const std::string& name) {
  return std::string(PAPER_MESH_DIR) + "/" + name + ".off";
}

/// Every triangle split in four at its edge midpoints (as lab/scripts/scale_benchmark.py does): the
/// same surface at twice the resolution.
inline Mesh split_in_four(const Mesh& mesh) {
  const Positions x = positions_from_mesh(mesh);
  const Faces f = faces_array(mesh);
  std::vector<Vec3> points;
  for (Eigen::Index i = 0; i < x.rows(); ++i) points.push_back(x.row(i).transpose());
  std::map<std::pair<int, int>, int> midpoints;
  auto midpoint = [&](int a, int b) {
    const std::pair<int, int> key(std::min(a, b), std::max(a, b));
    auto it = midpoints.find(key);
    if (it != midpoints.end()) return it->second;
    points.push_back(0.5 * (points[static_cast<std::size_t>(a)] + points[static_cast<std::size_t>(b)]));
    return midpoints[key] = static_cast<int>(points.size()) - 1;
  };
  TriMesh out;
  std::vector<std::array<int, 3>> faces;
  for (Eigen::Index j = 0; j < f.rows(); ++j) {
    const int a = f(j, 0), b = f(j, 1), c = f(j, 2);
    const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    faces.push_back({a, ab, ca});
    faces.push_back({ab, b, bc});
    faces.push_back({ca, bc, c});
    faces.push_back({ab, bc, ca});
  }
  out.x.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) out.x.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
  out.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t j = 0; j < faces.size(); ++j)
    for (int k = 0; k < 3; ++k) out.faces(static_cast<Eigen::Index>(j), k) = faces[j][k];
  return to_surface_mesh(out);
}

/// The default run (200 frames, every default) of `mesh`, checked for new self-intersections at the end.
inline RunResult default_run(const Mesh& mesh) {
  RunOptions o;
  o.sim.validate = ValidateMode::End;
  return run_contraction(mesh, o);
}

/// Checks issue "Control" item 5 on one mesh: the default run (200 frames, every default) ends
/// within 0.006 of the V/V0 the README states for it (`readme`, written in the calling test: two
/// decimals, so 0.005 of rounding, and 0.001 for the kernels of another CPU), with
/// no new self-intersection. The README's numbers are the documented behaviour: the air balance
/// (0.5) sets them, the shell's stiffness and the pressure the few hundredths above it, so
/// DEFAULT_AIR_BALANCE moved from 0.5 to 0.7 fails this (checked as --air-balance 0.7 on the
/// same runs: the end moves to the new balance).
inline void check_default_run_ratio(const std::string& name, double readme) {
  const std::string path = target_mesh_path(name);
  if (!std::filesystem::exists(path))
    GTEST_SKIP() << path << " is absent: run scripts/fetch_paper_meshes.sh";
  const RunResult r = default_run(load_target_mesh(name));
  ASSERT_EQ(r.status, RunStatus::Completed) << r.message;
  EXPECT_EQ(r.frames_run, 200) << name;
  EXPECT_NEAR(r.final_volume_ratio, readme, 0.006) << name;
  EXPECT_EQ(r.new_intersections, 0) << name;
  std::cout << "default run " << name << ": V/V0 " << r.final_volume_ratio << " (README " << readme << ")\n";
}

/// Issue "Control", item 3: `options` on icospheres of levels 2 to max_level (320, 1280, 5120,
/// 20480 faces) end within 0.02 of each other in V/V0, below 0.8 (they must contract, not agree by
/// staying put), without a new self-intersection when options.sim.validate asks for the check.
inline void check_icospheres_end_alike(const RunOptions& options, int max_level,
                                       const std::string& label) {
  double lowest = 1.0, highest = 0.0;
  for (int levels = 2; levels <= max_level; ++levels) {
    const RunResult r = run_contraction(to_surface_mesh(icosphere(levels)), options);
    ASSERT_EQ(r.status, RunStatus::Completed) << r.message;
    if (options.sim.validate != ValidateMode::Off) {
      EXPECT_EQ(r.new_intersections, 0);
    }
    lowest = std::min(lowest, r.final_volume_ratio);
    highest = std::max(highest, r.final_volume_ratio);
    std::cout << label << " icosphere of " << 20 * (1 << (2 * levels)) << " faces: V/V0 "
              << r.final_volume_ratio << "\n";
  }
  EXPECT_LE(highest - lowest, 0.02) << label;
  EXPECT_LT(highest, 0.8) << label;
}

/// A local-contraction run on meshes/bumpy_sphere.off with its three known bumps
/// (meshes/bumpy_sphere.bumps.txt) as the regions, no overall pressure.
inline RunResult bumpy_sphere_contraction(double shrink) {
  RunOptions o;
  o.sim.pressure = 0.0;
  o.sim.region_shrink = shrink;
  o.regions = RegionSource::File;
  o.region_file = std::string(MESH_DIR) + "/bumpy_sphere.bumps.txt";
  o.sim.validate = ValidateMode::End;
  return run_contraction(read_input_mesh(std::string(MESH_DIR) + "/bumpy_sphere.off"), o);
}

}  // namespace shellcontract::test
