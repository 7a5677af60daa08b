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
#include "support/cancel_probe.hpp"
#include "support/cgal_mesh.hpp"

namespace shellcontract {
namespace {

/// Level 6: 81920 faces, several CANCELLATION_CHUNKs.
const Mesh& sphere() {
  static const Mesh mesh = test::to_surface_mesh(test::icosphere(6));
  return mesh;
}

using test::expect_heard_inside;
using test::questions_of_a_whole_call;

/// Heard at its start and at its second question.
void expect_heard_inside(const char* what, const std::function<void()>& call) {
  expect_heard_inside(what, call, 2);
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
