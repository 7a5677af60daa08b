// The regions and fibre directions travel as face maps (design.md data flow): face lists given
// in the options become "f:region", a map already on the input mesh is read as it is, and the
// anisotropy setup stores "f:fiber_dir" and builds its constraints from it.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "shellcontract/core/error.hpp"
#include "shellcontract/geometry/region_selection.hpp"
#include "shellcontract/mesh/properties.hpp"
#include "shellcontract/sim/simulator.hpp"
#include "support/cgal_mesh.hpp"

namespace shellcontract {
namespace {

SimOptions anisotropic_options() {
  SimOptions opt;
  opt.frames = 10;
  opt.pressure = 3.0;
  opt.collisions = false;
  opt.solver.aniso = AnisoKind::Arap;
  return opt;
}

TEST(AnisotropyMaps, FaceListsBecomeTheRegionMapAndFibresAreStored) {
  const Mesh mesh = test::to_surface_mesh(test::icosphere(2));
  SimOptions opt = anisotropic_options();
  opt.anisotropy.regions = {{7, 3, 5}, {40, 41}};  // unsorted on purpose
  const Simulator sim(mesh, opt);
  const std::vector<int> expected = face_ids_from_regions(opt.anisotropy.regions, mesh.number_of_faces());
  EXPECT_EQ(stored_regions(sim.rest_mesh()), expected);
  EXPECT_EQ(sim.region_count(), 2u);
  EXPECT_EQ(sim.anisotropy_report().faces, 5u);
  const auto fiber = property::get_map<FaceIndex, Vec2>(sim.rest_mesh(), property::FIBER_DIR);
  for (FaceIndex f : sim.rest_mesh().faces()) {
    if (expected[f.idx()] >= 0) {
      EXPECT_NEAR(fiber[f].norm(), 1.0, 1e-12) << "face " << f.idx();
    } else {
      EXPECT_EQ(fiber[f], Vec2(1.0, 0.0)) << "face " << f.idx();
    }
  }
  // Toward the centre: the two faces of the second region point at each other's side, so their
  // fibres differ (the map holds per-face values, not one default).
  EXPECT_NE(fiber[FaceIndex(40)], Vec2(1.0, 0.0));
}

TEST(AnisotropyMaps, RegionMapOnTheInputMeshIsWhatTheSimulatorUses) {
  Mesh marked = test::to_surface_mesh(test::icosphere(2));
  const Mesh plain = marked;
  SimOptions with_lists = anisotropic_options();
  with_lists.anisotropy.regions = {{3, 5, 7}, {40, 41}};  // ascending: the map's order
  store_regions(marked, face_ids_from_regions(with_lists.anisotropy.regions, marked.number_of_faces()));

  Simulator by_lists(plain, with_lists);
  Simulator by_map(marked, anisotropic_options());
  Simulator without(plain, anisotropic_options());
  EXPECT_EQ(by_map.region_count(), 2u);
  EXPECT_EQ(without.region_count(), 0u);
  while (!by_lists.finished()) {
    by_lists.step();
    by_map.step();
    without.step();
  }
  EXPECT_EQ(by_map.positions(), by_lists.positions()) << "the map and the same lists must give the same run";
  EXPECT_NE(without.positions(), by_lists.positions()) << "the regions must change the run, or this test cannot fail";
}

TEST(AnisotropyMaps, BadFaceListsAreRefused) {
  const Mesh mesh = test::to_surface_mesh(test::icosphere(1));
  SimOptions opt = anisotropic_options();
  opt.anisotropy.regions = {{0, 1}, {1}};
  EXPECT_THROW(Simulator(mesh, opt), UsageError);
  opt.anisotropy.regions = {{static_cast<int>(mesh.number_of_faces())}};
  EXPECT_THROW(Simulator(mesh, opt), UsageError);
}

}  // namespace
}  // namespace shellcontract
