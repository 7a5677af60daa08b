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

#include "fem/triangle_element.hpp"
#include "pbd/constraint_batches.hpp"
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

// ------------------------------------------------------------------ membranes

struct MembraneScene : Scene {
  std::vector<PackedMembrane> records;  ///< grouped by colour
};

inline PackedMembrane packed_on(const Vec3& a, const Vec3& b, const Vec3& c, std::array<int, 3> v) {
  const TriangleRest r = triangle_rest(a, b, c);
  MembraneConstraint m;
  m.v = v;
  m.Dm_inv = r.Dm_inv;
  m.rest_area = r.area;
  m.max_step = 1e9;
  return pack_membrane(m);
}

/// n triangles (3k, 3k+1, 3k+2) in colour 0, then n triangles (3k+1, 3(k+1)+2, 3(k+2)) in
/// colour 1 (indices mod 3n): no two of a colour share a vertex, colour 1 reads colour 0's
/// results. The first constraints are the special cases named below.
inline MembraneScene membrane_scene(int n, std::mt19937& rng) {
  MembraneScene s;
  const std::vector<Vec3> rest = random_rest_and_start(s, 3 * n, 0.8, 0.15, rng);
  auto set = [&](int i, const Vec3& p) { for (int d = 0; d < 3; ++d) s.x0[3 * i + d] = p(d); };
  for (int k = 0; k < n; ++k)
    s.records.push_back(packed_on(rest[3 * k], rest[3 * k + 1], rest[3 * k + 2], {3 * k, 3 * k + 1, 3 * k + 2}));
  // Special cases in colour 0 (each touches only its own three vertices there).
  for (int i = 0; i < 3; ++i) set(i, rest[i]);                      // 0: at rest, E = 0: skipped
  s.w[3] = s.w[4] = s.w[5] = 0.0;                                   // 1: all pinned, G = 0: skipped
  s.w[6] = 0.0;                                                     // 2: one pinned vertex
  set(11, 0.5 * (Vec3(s.x0[27], s.x0[28], s.x0[29]) + Vec3(s.x0[30], s.x0[31], s.x0[32])));  // 3: collinear
  {                                                                 // 4: inverted (two corners swapped)
    for (int d = 0; d < 3; ++d) std::swap(s.x0[36 + d], s.x0[39 + d]);
  }
  for (int i = 15; i < 18; ++i) set(i, Vec3(0.3, -0.2, 0.1));       // 5: collapsed to a point (F = 0)
  s.records[6].max_step = 1e-3;                                     // 6: the clamp acts
  s.records[7].max_step = 1e-3;
  for (int k = 0; k < n; ++k) {
    const int a = 3 * k + 1, b = 3 * ((k + 1) % n) + 2, c = 3 * ((k + 2) % n);
    s.records.push_back(packed_on(rest[a], rest[b], rest[c], {a, b, c}));
  }
  s.colours = {0, static_cast<std::size_t>(n), static_cast<std::size_t>(2 * n)};
  return s;
}

}  // namespace shellcontract::test
