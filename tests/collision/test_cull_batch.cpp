// cull_batch against the scalar swept_boxes_apart and nonpenetration_filter_culls (with the
// coarse rounding bound, FilterBound::Coarse), and its axes output against separating_axes_culls:
// the same answer for every stencil (the batch only shares the work), on random, near-coplanar,
// degenerate, boundary and non-finite stencils, and on pairs that move together.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "collision/ccd.hpp"
#include "collision/cull_batch.hpp"
#include "support/random_geometry.hpp"

namespace shellcontract {
namespace {

/// Start and end positions of many stencils, four vertices each (stencil s uses rows 4s..4s+3).
struct Stencils {
  std::vector<double> x0, x1;
  std::vector<CcdPrimitive> kind;
  void add(CcdPrimitive k, const CcdStencil& s0, const CcdStencil& s1) {
    for (int j = 0; j < 4; ++j)
      for (int d = 0; d < 3; ++d) {
        x0.push_back(s0[static_cast<std::size_t>(j)][d]);
        x1.push_back(s1[static_cast<std::size_t>(j)][d]);
      }
    kind.push_back(k);
  }
  std::size_t size() const { return kind.size(); }
  CcdStencil at(const std::vector<double>& x, std::size_t s) const {
    CcdStencil out;
    for (int j = 0; j < 4; ++j)
      out[static_cast<std::size_t>(j)] = Vec3(x[12 * s + 3 * static_cast<std::size_t>(j)],
                                              x[12 * s + 3 * static_cast<std::size_t>(j) + 1],
                                              x[12 * s + 3 * static_cast<std::size_t>(j) + 2]);
    return out;
  }
};

Stencils make_stencils(std::mt19937& rng) {
  Stencils st;
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const double inf = std::numeric_limits<double>::infinity();
  for (CcdPrimitive kind : {CcdPrimitive::VertexFace, CcdPrimitive::EdgeEdge}) {
    for (int i = 0; i < 4000; ++i) {
      const int family = i % 8;
      CcdStencil s0, s1;
      const double spread = family == 0 ? 1.0 : 0.05;
      for (auto& p : s0) p = test::random_vec3(rng, spread);
      const double motion = family == 1 ? 0.0 : family == 2 ? 1e-3 : 0.05;
      for (int j = 0; j < 4; ++j)
        s1[static_cast<std::size_t>(j)] =
            s0[static_cast<std::size_t>(j)] + test::random_vec3(rng, motion);
      if (family == 3) {
        // Near-coplanar: flatten z by 1e-5 ... 1e-17, start and end; the flattest put the
        // coefficients within the rounding bound, where it decides.
        const double flat = std::pow(10.0, -5 - (i / 8) % 13);
        for (auto* s : {&s0, &s1})
          for (auto& p : *s) p.z() *= flat;
      } else if (family == 4) {
        // Degenerate: repeated points (zero-length edge, collinear triangle).
        s0[2] = s0[1];
        s1[2] = s1[1];
        s0[3] = 0.5 * (s0[0] + s0[1]);
        s1[3] = 0.5 * (s1[0] + s1[1]);
      } else if (family == 5) {
        // Boxes exactly tau = 1/16 apart on x (binary fractions: the gap is exact), or closer.
        const double gap = i % 3 == 0 ? 0.0625 : i % 3 == 1 ? 0.0625 * (1 + 1e-15) : 0.03125;
        for (auto* s : {&s0, &s1}) {
          const int split = kind == CcdPrimitive::VertexFace ? 1 : 2;
          for (int j = 0; j < 4; ++j) (*s)[static_cast<std::size_t>(j)].x() = j < split ? 0.0 : gap;
        }
      } else if (family == 6) {
        // Huge coordinates: the box test's probe sum may overflow.
        for (auto* s : {&s0, &s1})
          for (auto& p : *s) p *= 1e307;
      } else if (family == 7 && i % 16 == 7) {
        // Non-finite.
        s1[static_cast<std::size_t>(i % 4)].y() = (i / 16) % 2 == 0 ? inf : std::nan("");
      }
      st.add(kind, s0, s1);
    }
  }
  return st;
}

/// Calls visit(first stencil, ids, count) for batches of 1..4 consecutive stencils of one kind
/// (count cycling with the first stencil's index, cut where the kind changes).
template <class Visit>
void for_each_batch(const Stencils& st, Visit visit) {
  for (std::size_t s = 0; s < st.size();) {
    const int want_count = 1 + static_cast<int>(s % 4);
    std::array<int, 4> v[CULL_LANES];
    int count = 0;
    while (count < want_count && s + static_cast<std::size_t>(count) < st.size() &&
           st.kind[s + static_cast<std::size_t>(count)] == st.kind[s]) {
      const int base = 4 * static_cast<int>(s + static_cast<std::size_t>(count));
      v[count++] = {base, base + 1, base + 2, base + 3};
    }
    visit(s, v, count);
    s += static_cast<std::size_t>(count);
  }
}

TEST(CullBatch, SameAnswersAsTheScalarFunctions) {
  if (!cull_batch_avx2_available()) {
    GTEST_SKIP() << "this CPU has no AVX2: cull_batch runs the scalar functions themselves";
  }
  std::mt19937 rng(20261123);
  const Stencils st = make_stencils(rng);
  std::int64_t box = 0, filter_only = 0, kept = 0, compared = 0, bound_decides = 0;
  for (double tol : {0.0, 1e-4, 0.0625}) {
    for_each_batch(st, [&](std::size_t s, const std::array<int, 4>* v, int count) {
      std::uint8_t culled[CULL_LANES] = {7, 7, 7, 7};
      cull_batch(st.kind[s], st.x0.data(), st.x1.data(), v, count, tol, culled);
      for (int k = 0; k < count; ++k) {
        const std::size_t id = s + static_cast<std::size_t>(k);
        const CcdStencil s0 = st.at(st.x0, id), s1 = st.at(st.x1, id);
        const bool by_box = swept_boxes_apart(st.kind[s], s0, s1, tol);
        const bool by_filter =
            nonpenetration_filter_culls(st.kind[s], s0, s1, tol, FilterBound::Coarse);
        ASSERT_EQ(culled[k], by_box || by_filter ? 1 : 0)
            << "stencil " << id << " (family " << (id % 4000) % 8 << "), tolerance " << tol;
        // Stencils that the tight bound would cull and the coarse one keeps: the rounding bound
        // itself is compared there.
        bound_decides +=
            !by_filter && nonpenetration_filter_culls(st.kind[s], s0, s1, tol, FilterBound::Tight);
        box += by_box;
        filter_only += !by_box && by_filter;
        kept += !by_box && !by_filter;
        ++compared;
      }
      for (int k = count; k < CULL_LANES; ++k) EXPECT_EQ(culled[k], 7) << "lane past count written";
    });
  }
  // Every outcome occurs often, so the comparison covers each path of the batch code.
  EXPECT_GT(box, 1000);
  EXPECT_GT(filter_only, 1000);
  EXPECT_GT(kept, 1000);
  EXPECT_GT(bound_decides, 100);
  EXPECT_EQ(compared, 3 * static_cast<std::int64_t>(st.size()));
}

/// Pairs that move together: apart by `gap` along x at the start (A's points at x >= gap, B's at
/// x <= 0), then all moved by a shared 0.3 along x plus each point's own motion of up to 0.05 per
/// coordinate. Their swept boxes overlap (the shared motion is larger than the gap), so the box
/// test keeps them; the differences a - b at each end decide the axes cull.
void add_moving_together(std::mt19937& rng, Stencils& st) {
  std::uniform_real_distribution<double> gap(0.0, 0.2), unit(0.0, 1.0);
  for (CcdPrimitive kind : {CcdPrimitive::VertexFace, CcdPrimitive::EdgeEdge}) {
    const int split = kind == CcdPrimitive::VertexFace ? 1 : 2;
    for (int i = 0; i < 3000; ++i) {
      const double g = gap(rng);
      CcdStencil s0, s1;
      for (int j = 0; j < 4; ++j) {
        Vec3& p = s0[static_cast<std::size_t>(j)];
        p = test::random_vec3(rng, 0.05);
        p.x() = j < split ? g + 0.05 * unit(rng) : -0.05 * unit(rng);
        s1[static_cast<std::size_t>(j)] = p + Vec3(0.3, 0.0, 0.0) + test::random_vec3(rng, 0.05);
      }
      st.add(kind, s0, s1);
    }
  }
}

TEST(CullBatch, AxesOutputIsTheScalarAxesCull) {
  if (!cull_batch_avx2_available()) {
    GTEST_SKIP() << "this CPU has no AVX2: cull_batch runs the scalar functions themselves";
  }
  std::mt19937 rng(20261129);
  Stencils st = make_stencils(rng);
  add_moving_together(rng, st);
  std::int64_t axes_only = 0, axes_and_filter = 0, neither = 0;
  for (double tol : {0.0, 1e-4, 0.0625}) {
    for_each_batch(st, [&](std::size_t s, const std::array<int, 4>* v, int count) {
      std::uint8_t culled[CULL_LANES], axes[CULL_LANES] = {7, 7, 7, 7};
      cull_batch(st.kind[s], st.x0.data(), st.x1.data(), v, count, tol, culled, CullIsa::Auto,
                 axes);
      for (int k = 0; k < count; ++k) {
        const std::size_t id = s + static_cast<std::size_t>(k);
        const CcdStencil s0 = st.at(st.x0, id), s1 = st.at(st.x1, id);
        const bool want = separating_axes_culls(st.kind[s], s0, s1, tol);
        ASSERT_EQ(axes[k], want ? 1 : 0) << "stencil " << id << ", tolerance " << tol;
        axes_only += want && !culled[k];
        axes_and_filter += want && culled[k];
        neither += !want && !culled[k];
      }
      for (int k = count; k < CULL_LANES; ++k) EXPECT_EQ(axes[k], 7) << "lane past count written";
    });
  }
  // The axes settle many pairs the box test and the filter keep (the collision step's reason to
  // ask), and many of both kinds of answer occur.
  EXPECT_GT(axes_only, 1000);
  EXPECT_GT(axes_and_filter, 1000);
  EXPECT_GT(neither, 1000);
}

TEST(CullBatch, ScalarIsaAndNonFiniteInputAreNeverCulled) {
  // Far apart but with a NaN or an infinity: never culled, on either path.
  const double inf = std::numeric_limits<double>::infinity();
  for (double bad : {inf, -inf, std::nan("")}) {
    std::vector<double> x0 = {0, 0, 0, 10, 0, 0, 10, 1, 0, 10, 0, 1};
    std::vector<double> x1 = x0;
    x1[4] = bad;
    const std::array<int, 4> v[1] = {{0, 1, 2, 3}};
    for (CullIsa isa : {CullIsa::Auto, CullIsa::Scalar}) {
      std::uint8_t culled[1] = {7};
      cull_batch(CcdPrimitive::VertexFace, x0.data(), x1.data(), v, 1, 1e-4, culled, isa);
      EXPECT_EQ(culled[0], 0) << "bad value " << bad;
      x1[4] = 0.0;  // the same stencil, finite: culled by the boxes
      cull_batch(CcdPrimitive::VertexFace, x0.data(), x1.data(), v, 1, 1e-4, culled, isa);
      EXPECT_EQ(culled[0], 1);
      x1[4] = bad;
    }
  }
}

}  // namespace
}  // namespace shellcontract
