// A run's cancel inside the single long calls of its region selection (core/cancellation.hpp):
// the curvature, the finder's mesh arrays and the cotangent Laplacian's assembly. Before, each
// asked nothing and ran to its end on a large mesh; these tests failed there (no throw).
// Each test counts the scope's questions: a call that stops at the n-th question, where a whole
// call asks more, stopped before its end.
#include <gtest/gtest.h>

#include <functional>

#include "core/cancellation.hpp"
#include "geometry/cap_internal.hpp"
#include "geometry/cotan_laplacian.hpp"
#include "geometry/curvature.hpp"
#include "mesh/eigen_point_map.hpp"
#include "support/cgal_mesh.hpp"

namespace shellcontract {
namespace {

/// Level 6: 81920 faces, several CANCELLATION_CHUNKs.
const Mesh& sphere() {
  static const Mesh mesh = test::to_surface_mesh(test::icosphere(6));
  return mesh;
}

/// How many times `call` asks a scope that never says cancelled.
int questions_of_a_whole_call(const std::function<void()>& call) {
  int asked = 0;
  const CancellationScope scope([&] {
    ++asked;
    return false;
  });
  call();
  return asked;
}

/// Runs `call` under a scope that says cancelled from its `at`-th question on; true when the
/// call threw PreparationCancelled at that question.
bool stops_at(int at, const std::function<void()>& call) {
  int asked = 0;
  const CancellationScope scope([&] { return ++asked >= at; });
  try {
    call();
  } catch (const PreparationCancelled&) {
    return asked == at;
  }
  return false;
}

/// The cancel at the first and the second question ends `call`, which asks more than twice
/// in all: it is heard at the call's start and inside it.
void expect_heard_inside(const char* what, const std::function<void()>& call) {
  const int whole = questions_of_a_whole_call(call);
  EXPECT_GT(whole, 2) << what << " asks " << whole << " times";
  EXPECT_TRUE(stops_at(1, call)) << what << ": a cancel at its start";
  EXPECT_TRUE(stops_at(2, call)) << what << ": a cancel inside it";
}

TEST(CancelLongCalls, TheCurvatureHearsACancelPerChunkOfFaces) {
  const Positions x = positions_from_mesh(sphere());
  expect_heard_inside("compute_curvature", [&] { compute_curvature(sphere(), x); });
}

TEST(CancelLongCalls, TheFindersMeshArraysHearACancel) {
  const Positions x = positions_from_mesh(sphere());
  expect_heard_inside("mesh_arrays", [&] { detail::mesh_arrays(sphere(), x); });
  expect_heard_inside("start_finder", [&] { detail::start_finder(sphere(), x); });
}

// Its parallel blocks ask on the run's thread only, the others see the cancel once that thread
// has: the count of a whole call depends on the threads, never below its passes.
TEST(CancelLongCalls, TheLaplacianAssemblyHearsACancelBetweenItsPasses) {
  const Positions x = positions_from_mesh(sphere());
  const detail::MeshArrays m = detail::mesh_arrays(sphere(), x);
  expect_heard_inside("cotan_laplacian", [&] { detail::cotan_laplacian(m.tri, x); });
}

// Without a scope (a finder or the fields used on their own) nothing is asked and the results
// are the same.
TEST(CancelLongCalls, WithoutAScopeTheCallsRunAsBefore) {
  const Positions x = positions_from_mesh(sphere());
  const CurvatureField alone = compute_curvature(sphere(), x);
  CurvatureField asked;
  questions_of_a_whole_call([&] { asked = compute_curvature(sphere(), x); });
  EXPECT_EQ(alone.mean, asked.mean);
  EXPECT_EQ(alone.gaussian, asked.gaussian);
}

}  // namespace
}  // namespace shellcontract
