// `--dimple mirror` in a run (docs/math/region-mirror.md): the option reaches the simulator, and on
// bumpy_sphere's three bumps at -p 0 the mirrored dimples sink them locally, with the rest of the
// shell moving less than under the volume projection of the same dimples.
#include <gtest/gtest.h>

#include <string>

#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

RunResult bumps_at_rest_pressure(const std::string& dimple) {
  RunOptions o;
  set_run_option(o, "pressure", "0");
  set_run_option(o, "regions", std::string(test::MESH_DIR) + "/bumpy_sphere.bumps.txt");
  set_run_option(o, "dimple", dimple);
  set_run_option(o, "validate", "end");
  return run_contraction(read_input_mesh(std::string(test::MESH_DIR) + "/bumpy_sphere.off"), o);
}

TEST(RegionMirrorRun, TheOptionParsesAndRejectsOtherShapes) {
  RunOptions o;
  EXPECT_EQ(o.sim.dimple_shape, DimpleShape::Mirror);  // the default (region-mirror.md, 5)
  set_run_option(o, "dimple", "volume");
  EXPECT_EQ(o.sim.dimple_shape, DimpleShape::Volume);
  set_run_option(o, "dimple", "mirror");
  EXPECT_EQ(o.sim.dimple_shape, DimpleShape::Mirror);
  EXPECT_EQ(find_run_option("dimple")->get(o), "mirror");
  EXPECT_THROW(set_run_option(o, "dimple", "flat"), UsageError);
}

TEST(RegionMirrorRun, MirroredBumpsSinkLocally) {
  // Locality on the bumps: each sinks at least 1 % of the diagonal
  // on average and the rest of the shell (outside the bumps and their one-ring band) moves at
  // most a tenth of that, with no new self-intersection. The mirror strains no dimple face, so
  // the rest also moves less than with the volume projection, which leaves the dimple's shape
  // free (an independent run of the same dimples). Fails with a flattening for the reflection
  // (p - (p.n) n), a plane through the origin for the rim's, or without the similarity fit's
  // determinant correction.
  const RunResult mirror = bumps_at_rest_pressure("mirror");
  const RunResult volume = bumps_at_rest_pressure("volume");
  ASSERT_EQ(mirror.status, RunStatus::Completed) << mirror.message;
  ASSERT_EQ(volume.status, RunStatus::Completed) << volume.message;
  EXPECT_EQ(mirror.regions, 3u);
  EXPECT_EQ(mirror.new_intersections, 0);
  EXPECT_GE(mirror.region_inward_displacement, 0.01);
  EXPECT_LE(mirror.outside_region_displacement, 0.1 * mirror.region_inward_displacement)
      << "sink " << mirror.region_inward_displacement << ", rest "
      << mirror.outside_region_displacement;
  EXPECT_LT(mirror.outside_region_displacement, volume.outside_region_displacement);
}

}  // namespace
}  // namespace shellcontract
