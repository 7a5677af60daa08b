// The warning for the paper's flat-rest isometric bending under the XPBD shell, and the behaviour
// it warns of: with no pressure a sphere keeps its volume under the default dihedral bending and
// under the paper's PBD setting, and loses it under isometric bending with XPBD.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"
#include "support/cgal_mesh.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

bool warns_of_flat_rest(const RunOptions& o) {
  for (const std::string& w : ineffective_options(o))
    if (w.find("`bending` isometric has a flat rest state") != std::string::npos) return true;
  return false;
}

RunOptions unpressed(const char* solver, const char* bending) {
  RunOptions o;
  set_run_option(o, "solver", solver);
  set_run_option(o, "bending", bending);
  set_run_option(o, "pressure", "0");
  set_run_option(o, "frames", "100");
  resolve_run_options(o);
  return o;
}

TEST(BendingWarning, IsometricBendingUnderXpbdIsWarnedOf) {
  EXPECT_TRUE(warns_of_flat_rest(unpressed("xpbd", "isometric")));
  EXPECT_FALSE(warns_of_flat_rest(unpressed("pbd", "isometric")));  // the paper's setting
  EXPECT_FALSE(warns_of_flat_rest(unpressed("xpbd", "dihedral")));
}

TEST(BendingWarning, WhatItWarnsOfASphereContractsWithNoPressure) {
  const Mesh sphere = test::to_surface_mesh(test::icosphere(2));
  // A sphere at rest with nothing pushing on it: it should stay a sphere.
  EXPECT_GT(run_contraction(sphere, unpressed("xpbd", "dihedral")).final_volume_ratio, 0.99);
  EXPECT_GT(run_contraction(sphere, unpressed("pbd", "isometric")).final_volume_ratio, 0.99);
  // Flat at rest under the XPBD shell's stiffness: it does not.
  EXPECT_LT(run_contraction(sphere, unpressed("xpbd", "isometric")).final_volume_ratio, 0.9);
}

}  // namespace
}  // namespace shellcontract
