// The regions and fibre directions travel as face maps (design.md data flow): the regions are the
// "f:region" map of the mesh the Simulator is given (the run plan resolves a run's region source
// into it), and the anisotropy setup stores "f:fiber_dir" and builds its constraints from it.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "mesh/properties.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/regions.hpp"
#include "sim/simulator.hpp"
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

TEST(AnisotropyMaps, RegionMapIsKeptAndFibresAreStored) {
  Mesh mesh = test::to_surface_mesh(test::icosphere(2));
  const std::vector<int> expected =
      face_ids_from_regions({{7, 3, 5}, {40, 41}}, mesh.number_of_faces());  // unsorted on purpose
  store_regions(mesh, expected);
  const Simulator sim(mesh, anisotropic_options());
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
  store_regions(marked, face_ids_from_regions({{3, 5, 7}, {40, 41}}, marked.number_of_faces()));

  Simulator by_map(marked, anisotropic_options());
  Simulator without(plain, anisotropic_options());
  EXPECT_EQ(by_map.region_count(), 2u);
  EXPECT_EQ(without.region_count(), 0u);
  while (!by_map.finished()) {
    by_map.step();
    without.step();
  }
  EXPECT_NE(without.positions(), by_map.positions()) << "the regions must change the run";
}

TEST(AnisotropyMaps, BadFaceListsAreRefused) {
  const Mesh mesh = test::to_surface_mesh(test::icosphere(1));
  EXPECT_THROW(face_ids_from_regions({{0, 1}, {1}}, mesh.number_of_faces()), UsageError);
  EXPECT_THROW(face_ids_from_regions({{static_cast<int>(mesh.number_of_faces())}},
                                     mesh.number_of_faces()),
               UsageError);
}

}  // namespace
}  // namespace shellcontract
