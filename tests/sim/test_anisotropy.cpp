// The regions and fibre directions travel as face maps (architecture.md data flow): the regions are the
// "f:region" map of the mesh the Simulator is given (the run plan resolves a run's region source
// into it), and the anisotropy setup stores "f:fiber_dir" and builds its constraints from it.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "mesh/properties.hpp"
#include "sim/anisotropy.hpp"
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

TEST(AnisotropyMaps, FibreDirectionDoesNotDependOnTheLengthOfTheGivenDirection) {
  // --fiber X,Y,Z is a direction: any nonzero finite length gives the same fibre, bit for bit.
  // 1e200 made the in-plane length infinite (no fibre: a silent isotropic run) and 1e-200 made
  // it 0 (the fallback).
  const Vec3 T1 = Vec3(1, 2, 2) / 3.0, T2 = Vec3(2, -2, 1) / 3.0;  // orthonormal
  const Vec3 d(0.3, -1.1, 0.7);
  bool fallback = true;
  const Vec2 want = fiber_in_rest_frame(d, T1, T2, fallback);
  ASSERT_FALSE(fallback);
  EXPECT_NEAR(want.norm(), 1.0, 1e-15);
  for (double s : {1e-300, 1e-200, 1e-20, 0.5, 3.0, 1e20, 1e200, 1e300}) {
    const Vec2 got = fiber_in_rest_frame(s * d, T1, T2, fallback);
    EXPECT_FALSE(fallback) << "scale " << s;
    EXPECT_NEAR((got - want).norm(), 0.0, 1e-15) << "scale " << s;
  }
  // A power of two scales exactly: the same bits.
  EXPECT_EQ(fiber_in_rest_frame(std::ldexp(1.0, 600) * d, T1, T2, fallback), want);
  // Normal to the face: the fallback, at any length.
  for (double s : {1e-200, 1.0, 1e200}) {
    EXPECT_EQ(fiber_in_rest_frame(s * T1.cross(T2), T1, T2, fallback), Vec2(1.0, 0.0));
    EXPECT_TRUE(fallback) << "scale " << s;
  }
}

}  // namespace
}  // namespace shellcontract
