// Scenes for the batched projections' tests (tests/pbd/test_constraint_batches.cpp,
// test_dihedral_batches.cpp): random start states, their padded rows, the projection context, and
// the comparison of the AVX2 path with the scalar kernels.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "shellcontract/pbd/constraint_batches.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract::test {

inline constexpr double ALPHA_TILDE = 1e4;  // dt = 0.01, alpha = 1 (math-spec 9.2)

/// Scene of n constraints in two colours over disjoint-in-colour vertex sets.
struct Scene {
  std::vector<double> x0;           ///< 3 per vertex
  std::vector<double> w;
  std::vector<std::size_t> colours;  ///< colour offsets
};

/// Draws `count` random rest points, then fills the scene's start state with keep * rest +
/// noise * random offsets and random masses in [0.5, 2]. Returns the rest points.
inline std::vector<Vec3> random_rest_and_start(Scene& s, int count, double keep, double noise,
                                               std::mt19937& rng) {
  std::vector<Vec3> rest(static_cast<std::size_t>(count));
  for (Vec3& p : rest) p = random_vec3(rng);
  std::uniform_real_distribution<double> mass(0.5, 2.0);
  for (const Vec3& p : rest) {
    const Vec3 q = keep * p + noise * random_vec3(rng);
    s.x0.insert(s.x0.end(), {q.x(), q.y(), q.z()});
    s.w.push_back(1.0 / mass(rng));
  }
  return rest;
}

/// The padded rows (x, y, z, w) of a scene's start state.
inline std::vector<PaddedVertex> padded(const Scene& s) {
  std::vector<PaddedVertex> xw(s.w.size());
  pack_padded(s.x0.data(), s.w.data(), 0, xw.size(), xw.data());
  return xw;
}

/// Largest |x - ref| over every coordinate, against the tolerance 1e-12 |ref - x0| + 4 ulp(x0):
/// the AVX2 path may differ from the scalar one by rounding only (FMA), relative to the step.
inline void expect_close_to_step(const std::vector<double>& x, const std::vector<double>& ref,
                                 const std::vector<double>& x0, const char* what) {
  const double eps = std::numeric_limits<double>::epsilon();
  double moved = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    moved = std::max(moved, std::abs(ref[i] - x0[i]));
    EXPECT_LE(std::abs(x[i] - ref[i]), 1e-12 * std::abs(ref[i] - x0[i]) + 4 * eps * std::abs(x0[i]))
        << what << ": coordinate " << i << " batched " << x[i] << " scalar " << ref[i] << " start " << x0[i];
  }
  EXPECT_GT(moved, 1e-9) << what << ": the projections must move something";
}

/// The projection context of a scene's state (x, w), XPBD's alpha_tilde = ALPHA_TILDE.
inline ProjectionContext context(std::vector<double>& x, const std::vector<double>& w) {
  ProjectionContext ctx;
  ctx.x = x.data();
  ctx.w = w.data();
  ctx.energy_floor = 1e-16;
  ctx.alpha_tilde = ALPHA_TILDE;
  return ctx;
}

}  // namespace shellcontract::test
