// The default run ends each paper mesh at the V/V0 the README states, within 0.02 (the rest of
// the meshes in tests/long), and the local contraction's strength controls how far regions sink.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: temporary files of this process's own

#include <algorithm>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "shellcontract/options.hpp"
#include "shellcontract/regions.hpp"
#include "sim/region_volume.hpp"
#include "support/default_run_case.hpp"

namespace shellcontract {
namespace {

// README, "How much it contracts": "The paper's meshes end 200 default frames at V/V0 0.50
// (eight), 0.50 (hand), 0.53 (elk), 0.51 (bear), 0.51 (kitten)". The kitten, reconstructed from
// its point set first, is in tests/long.
TEST(Defaults, EightEndsAtTheReadmesRatio) { test::check_default_run_ratio("eight", 0.50); }
TEST(Defaults, HandEndsAtTheReadmesRatio) { test::check_default_run_ratio("hand", 0.50); }
TEST(Defaults, ElkEndsAtTheReadmesRatio) { test::check_default_run_ratio("elk", 0.53); }
TEST(Defaults, BearEndsAtTheReadmesRatio) { test::check_default_run_ratio("bear", 0.51); }

TEST(Defaults, IcospheresOf320To5120FacesEndAlike) {
  // Issue "Control", item 3 (the whole range to 20,480 faces: tests/long): the default run's
  // membrane is a material, so the end volume does not depend on the resolution. The paper's PBD
  // does (--solver pbd: 0.99, 0.69, 0.54 on these three).
  test::check_icospheres_end_alike(RunOptions{}, 4, "default");
}

TEST(Defaults, ThePapersSettingIsStillAvailable) {
  // --solver pbd --air-balance 0 --bending isometric -p 2: the paper's solver and constant
  // pressure crush the hand far below the default's end volume (lab/pages/defaults.md has the
  // measured end volume with collisions on).
  const std::string path = test::target_mesh_path("hand");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";
  RunOptions o;
  set_run_option(o, "solver", "pbd");
  o.sim.air_balance = 0.0;
  o.sim.bending = BendingModel::Isometric;
  o.sim.pressure = 2.0;
  const RunResult paper = run_contraction(test::load_target_mesh("hand"), o);
  ASSERT_EQ(paper.status, RunStatus::Completed) << paper.message;
  EXPECT_LT(paper.final_volume_ratio, 0.4);
}

TEST(LocalContraction, RegionsSinkMoreAsTheShrinkGrows) {
  // Monotone in the strength, and nothing at strength 0 (no pressure either: the shell is at
  // rest with the rest-aware bending); local at the default strength.
  double previous = -1.0;
  for (double s : {0.0, 0.3, DEFAULT_REGION_SHRINK, 1.0}) {
    const RunResult r = test::bumpy_sphere_contraction(s);
    ASSERT_EQ(r.status, RunStatus::Completed) << r.message;
    EXPECT_EQ(r.regions, 3u);
    EXPECT_EQ(r.new_intersections, 0) << "shrink " << s;
    if (s == 0.0) {
      EXPECT_LE(std::abs(r.region_inward_displacement), 1e-9);
    } else {
      EXPECT_GT(r.region_inward_displacement, previous) << "shrink " << s;
    }
    if (s == DEFAULT_REGION_SHRINK) {
      // Item 1 at the default strength: the bumps sink at least 1 % of the bounding-box diagonal
      // (the normalized unit) and 10x as far as the rest of the shell moves.
      EXPECT_GE(r.region_inward_displacement, 0.01);
      EXPECT_GE(r.region_inward_displacement, 10.0 * r.outside_region_displacement)
          << "rest moved " << r.outside_region_displacement;
    }
    previous = r.region_inward_displacement;
    std::cout << "bumpy_sphere shrink " << s << ": region sink " << r.region_inward_displacement
              << ", rest moved " << r.outside_region_displacement << " (normalized), V/V0 "
              << r.final_volume_ratio << "\n";
  }
}

TEST(LocalContraction, TopOfRangeSinksTheBumpsDeepAndLocally) {
  // Issue "Local contraction", item 2: at --region-shrink 1 (the mirror image of each bump) the
  // centre of every bump sinks by at least 30 % of its radius, with the regions sinking at least
  // 10x as far as the rest of the shell moves (item 1's locality) and no new self-intersection.
  const RunResult r = test::bumpy_sphere_contraction(1.0);
  ASSERT_EQ(r.status, RunStatus::Completed) << r.message;
  EXPECT_EQ(r.new_intersections, 0);
  EXPECT_GE(r.region_inward_displacement, 10.0 * r.outside_region_displacement)
      << "sink " << r.region_inward_displacement << ", rest " << r.outside_region_displacement;
  const Mesh input = read_input_mesh(std::string(test::MESH_DIR) + "/bumpy_sphere.off");
  const Positions rest = positions_from_mesh(input);
  const Faces faces = faces_array(input);
  Positions normal = Positions::Zero(rest.rows(), 3);
  for (Eigen::Index j = 0; j < faces.rows(); ++j) {
    const Vec3 a = rest.row(faces(j, 0)), b = rest.row(faces(j, 1)), c = rest.row(faces(j, 2));
    for (int k = 0; k < 3; ++k) normal.row(faces(j, k)) += (b - a).cross(c - a).transpose();
  }
  std::ifstream in(std::string(test::MESH_DIR) + "/bumpy_sphere.bumps.txt");
  int bumps = 0;
  for (std::string line; std::getline(in, line);) {
    std::istringstream ids(line);
    std::vector<int> region;
    for (int f; ids >> f;) region.push_back(f);
    if (region.empty()) continue;
    ++bumps;
    const RegionCap cap = make_region_cap(faces, region);
    Vec3 c = Vec3::Zero(), axis = Vec3::Zero();
    for (int k : cap.rim) c += Vec3(rest.row(cap.vertices[static_cast<std::size_t>(k)]));
    c /= static_cast<double>(cap.rim.size());
    for (int v : cap.vertices) axis += Vec3(normal.row(v));
    axis.normalize();
    double radius = 0.0;
    for (int k : cap.rim) radius += (Vec3(rest.row(cap.vertices[static_cast<std::size_t>(k)])) - c).norm();
    radius /= static_cast<double>(cap.rim.size());
    int apex = cap.vertices.front();
    for (int v : cap.vertices)
      if ((Vec3(rest.row(v)) - c).dot(axis) > (Vec3(rest.row(apex)) - c).dot(axis)) apex = v;
    const double sink =
        -(Vec3(r.positions.row(apex)) - Vec3(rest.row(apex))).dot(Vec3(normal.row(apex)).normalized());
    EXPECT_GE(sink, 0.3 * radius) << "bump " << bumps << ": centre sink " << sink << ", radius " << radius;
  }
  EXPECT_EQ(bumps, 3);
}

/// The -p 0 run of `shellcontract regions MESH --face-list F [thresholds]` then
/// `shellcontract run MESH -p 0 --regions F`, the way README's task "Sink chosen regions" does it.
RunResult face_list_contraction(const std::string& name, const RegionOptions& thresholds) {
  const Mesh mesh = test::load_target_mesh(name);
  const std::vector<int> ids =
      select_spherical_regions(mesh, positions_from_mesh(mesh), thresholds);
  const std::string file =
      (std::filesystem::temp_directory_path() /
       ("shellcontract_" + std::to_string(::getpid()) + "_" + name + "_regions.txt"))
          .string();
  write_region_file(file, ids);
  RunOptions o;
  o.sim.pressure = 0.0;
  o.regions = RegionSource::File;
  o.region_file = file;
  o.sim.validate = ValidateMode::End;
  const RunResult r = run_contraction(mesh, o);
  std::filesystem::remove(file);
  return r;
}

void expect_local(const std::string& name, const RunResult& r) {
  ASSERT_EQ(r.status, RunStatus::Completed) << r.message;
  EXPECT_GT(r.regions, 0u);
  EXPECT_EQ(r.new_intersections, 0);
  EXPECT_GE(r.region_inward_displacement, 0.01) << name;
  EXPECT_GE(r.region_inward_displacement, 10.0 * r.outside_region_displacement)
      << name << ": sink " << r.region_inward_displacement << ", rest "
      << r.outside_region_displacement;
}

TEST(LocalContraction, FaceListsOfTheHandAndBearSinkLocally) {
  // Issue "Local contraction", item 1 on the hand and bear, with the face lists that
  // `shellcontract regions` writes at its default thresholds (the fingertips; bear's ears, head
  // and paws: issue "Regions a person would choose").
  for (const char* name : {"hand", "bear"})
    if (!std::filesystem::exists(test::target_mesh_path(name)))
      GTEST_SKIP() << name << " is absent";
  // Fails with: the former default --dimple volume, whose dimple is not isometric, so the
  // nearly bending-free shell drifts under it (lab/regions/locality.md): the rest then moves far
  // more than a tenth of the sink on both meshes.
  expect_local("hand", face_list_contraction("hand", RegionOptions{}));
  expect_local("bear", face_list_contraction("bear", RegionOptions{}));
}

TEST(LocalContraction, BearsAutomaticRegionsSinkTenTimesFartherThanTheRestMoves) {
  // Issue "Regions a person would choose", item 2, on bear: at -p 0 over the default 200 frames,
  // every region the finder chooses sinks at least ten times as far as the shell away from the
  // regions moves, with no new self-intersection. Fails without the dimple's rest state
  // (docs/math/region-mirror.md, section 6): the placed dimples' own stress then kept pulling
  // the shell, whose rest moved 0.17 of the smallest sink. The hand and the elk do not pass yet
  // (lab/regions/rest_over_time.md).
  if (!std::filesystem::exists(test::target_mesh_path("bear"))) GTEST_SKIP() << "bear is absent";
  const RunResult r = face_list_contraction("bear", RegionOptions{});
  ASSERT_EQ(r.status, RunStatus::Completed) << r.message;
  EXPECT_EQ(r.new_intersections, 0);
  ASSERT_FALSE(r.region_sinks.empty());
  const double smallest = *std::min_element(r.region_sinks.begin(), r.region_sinks.end());
  EXPECT_GE(smallest, 10.0 * r.outside_region_displacement)
      << "smallest sink " << smallest << ", rest " << r.outside_region_displacement;
}

TEST(LocalContraction, UnderTheDefaultPressureTheBumpsSinkTwiceAsFar) {
  // Issue "Local contraction", item 3: in the default run (the global pressure on) the regions
  // sink at least twice as far with the local contraction as without it (--inward none), with
  // no new self-intersection. The dimple alone, bounded by the bump's mirror image, gave 1.37x.
  auto run = [](InwardTerm inward) {
    RunOptions o;
    o.sim.inward_term = inward;
    o.regions = RegionSource::File;
    o.region_file = std::string(test::MESH_DIR) + "/bumpy_sphere.bumps.txt";
    o.sim.validate = ValidateMode::End;
    return run_contraction(read_input_mesh(std::string(test::MESH_DIR) + "/bumpy_sphere.off"), o);
  };
  const RunResult off = run(InwardTerm::None), on = run(InwardTerm::Volume);
  ASSERT_EQ(off.status, RunStatus::Completed) << off.message;
  ASSERT_EQ(on.status, RunStatus::Completed) << on.message;
  EXPECT_EQ(on.regions, 3u);
  EXPECT_EQ(on.new_intersections, 0);
  ASSERT_GT(off.region_inward_displacement, 0.0);
  EXPECT_GE(on.region_inward_displacement, 2.0 * off.region_inward_displacement)
      << "on " << on.region_inward_displacement << ", off " << off.region_inward_displacement;
}

}  // namespace
}  // namespace shellcontract
