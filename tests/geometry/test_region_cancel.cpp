// The public region search's cancel hook (RegionOptions::cancelled): a caller outside a run
// (Python's regions(), asking its signal handlers) stops the search with RegionSearchCancelled.
// Before, the search's cancellation points asked only a run's scope, which the public functions had
// no way to open: Ctrl-C during regions() waited for the search's end.
#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

#include "core/cancellation.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/regions.hpp"
#include "support/cgal_mesh.hpp"
#include "support/mesh_fixtures.hpp"
#include "support/region_fixtures.hpp"

namespace shellcontract {
namespace {

/// bumpy_sphere split in four twice (20480 faces): its three bumps are found, and the long loops
/// run over more than one CANCELLATION_CHUNK of faces.
const test::TriMesh& bumps() {
  static const test::TriMesh m = test::split_in_four(test::split_in_four(
      test::to_tri_mesh(read_input_mesh(std::string(test::MESH_DIR) + "/bumpy_sphere.off"))));
  return m;
}

const Mesh& bumps_mesh() {
  static const Mesh mesh = test::to_surface_mesh(bumps());
  return mesh;
}

/// A point just above the largest bump of `bumps()` (the first region of the cap finder).
Vec3 bump_point() {
  RegionReport report;
  select_spherical_regions(bumps_mesh(), bumps().x, RegionOptions{}, &report);
  return report.regions.at(0).centre * 1.5;
}

/// Every public search of the regions, with `o`.
std::vector<std::pair<std::string, std::function<std::vector<int>(const RegionOptions&)>>>
searches() {
  const auto with = [](RegionMethod method) {
    return [method](RegionOptions o) {
      o.method = method;
      return select_spherical_regions(bumps_mesh(), bumps().x, o);
    };
  };
  const Vec3 at = bump_point();
  return {{"caps", with(RegionMethod::Caps)},
          {"tips", with(RegionMethod::Tips)},
          {"parts", with(RegionMethod::Parts)},
          {"select_regions_at",
           [at](const RegionOptions& o) {
             return select_regions_at(bumps_mesh(), bumps().x, {at}, o);
           }},
          {"mark_spherical_regions", [](const RegionOptions& o) {
             Mesh copy = bumps_mesh();
             mark_spherical_regions(copy, bumps().x, o);
             return stored_regions(copy);
           }}};
}

TEST(RegionCancel, AHookThatSaysStopEndsEverySearchWithRegionSearchCancelled) {
  for (const auto& [name, search] : searches()) {
    int asked = 0;
    RegionOptions o;
    o.cancelled = [&] {
      ++asked;
      return true;
    };
    EXPECT_THROW(search(o), RegionSearchCancelled) << name;
    EXPECT_EQ(asked, 1) << name << ": asked again after it said stop";
    // The search's scope ended with it: nothing after it asks the hook.
    EXPECT_EQ(CancellationScope::current(), nullptr) << name;
  }
}

TEST(RegionCancel, TheSearchHearsTheHookInsideItAndOnlyOnTheCallersThread) {
  for (const auto& [name, search] : searches()) {
    int whole = 0;
    bool elsewhere = false;
    const std::thread::id caller = std::this_thread::get_id();
    RegionOptions o;
    o.cancelled = [&] {
      ++whole;
      elsewhere = elsewhere || std::this_thread::get_id() != caller;
      return false;
    };
    const std::vector<int> asked_never = search(o);
    EXPECT_FALSE(elsewhere) << name;
    // A hook that never says stop changes nothing.
    EXPECT_EQ(asked_never, search(RegionOptions{})) << name;
    ASSERT_GT(whole, 4) << name << " asks its hook " << whole << " times";
    // Stopped halfway: at that question, not at the search's end.
    int asked = 0;
    const int at = whole / 2;
    o.cancelled = [&] { return ++asked >= at; };
    EXPECT_THROW(search(o), RegionSearchCancelled) << name;
    EXPECT_EQ(asked, at) << name;
  }
}

TEST(RegionCancel, ACancelledMarkLeavesTheMeshsMapsAlone) {
  Mesh mesh = bumps_mesh();
  RegionOptions o;
  int asked = 0;
  o.cancelled = [&] { return ++asked >= 3; };
  EXPECT_THROW(mark_spherical_regions(mesh, bumps().x, o), RegionSearchCancelled);
  EXPECT_FALSE((mesh.property_map<FaceIndex, int>("f:region").second));
}

// A hook on RegionOptions beside a run's scope (the library's own caller, say): the search asks
// the hook, and the run's scope is back once the search has ended.
TEST(RegionCancel, TheRunsScopeIsBackAfterASearchWithItsOwnHook) {
  const CancellationScope run([] { return false; });
  RegionOptions o;
  o.cancelled = [] { return true; };
  EXPECT_THROW(select_spherical_regions(bumps_mesh(), bumps().x, o), RegionSearchCancelled);
  EXPECT_EQ(CancellationScope::current(), &run);
}

}  // namespace
}  // namespace shellcontract
