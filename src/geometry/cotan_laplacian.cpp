// The cotangent Laplacian in compressed columns (cotan_laplacian.hpp). setFromTriplets inserts
// the triplets into a row-major buffer in list order, folds each entry's duplicates left to
// right (first value, then value + next) and transposes: so column c, row r holds the triplets
// (r, c, .) summed in list order. Here column v walks v's faces in increasing index, and each
// face's half-edges and their four triplets in list order, which is that same order.
// A run's cancel (core/cancellation.hpp) is heard between the passes and in each parallel block:
// on a large mesh the assembly is one of the single long calls of the region selection.
#include "geometry/cotan_laplacian.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <utility>

#include "core/cancellation.hpp"

namespace shellcontract::detail {

namespace {

/// The half-weight of the half-edge (i, j) of the face (i, j, o); false at a degenerate corner.
/// The finder's formula, operation for operation.
bool cotan_half_weight(const Positions& x, int i, int j, int o, double& w) {
  const Vec3 a = Vec3(x.row(i)) - Vec3(x.row(o)), b = Vec3(x.row(j)) - Vec3(x.row(o));
  const double cross = a.cross(b).norm();
  if (!(cross > 1e-14 * a.norm() * b.norm())) return false;  // degenerate: no weight
  w = 0.5 * a.dot(b) / cross;
  return true;
}

}  // namespace

Eigen::SparseMatrix<double> cotan_laplacian(const std::vector<std::array<int, 3>>& tri, const Positions& x) {
  const std::size_t nv = static_cast<std::size_t>(x.rows()), nf = tri.size();
  // Each half-edge's weight once (two columns read it); ok = 0 marks a degenerate corner.
  std::vector<double> w(3 * nf, 0.0);
  std::vector<char> ok(3 * nf, 0);
  const CancellationScope* const run = CancellationScope::current();
  cancellation_point();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nf, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    const CancellationScope::Join join(run);
    cancellation_point();
    for (std::size_t f = r.begin(); f != r.end(); ++f)
      for (std::size_t k = 0; k < 3; ++k)
        ok[3 * f + k] = cotan_half_weight(x, tri[f][k], tri[f][(k + 1) % 3], tri[f][(k + 2) % 3], w[3 * f + k]);
  });
  // Each vertex's faces in increasing index, once each (a face repeating a corner is listed once).
  cancellation_point();
  std::vector<int> vf_start(nv + 1, 0);
  const auto distinct = [](const std::array<int, 3>& t, std::size_t k) {
    return (k < 1 || t[k] != t[0]) && (k < 2 || t[k] != t[1]);
  };
  for (const auto& t : tri)
    for (std::size_t k = 0; k < 3; ++k)
      if (distinct(t, k)) ++vf_start[static_cast<std::size_t>(t[k]) + 1];
  for (std::size_t v = 0; v < nv; ++v) vf_start[v + 1] += vf_start[v];
  std::vector<int> vf(static_cast<std::size_t>(vf_start[nv]));
  {
    std::vector<int> fill(vf_start.begin(), vf_start.end() - 1);
    for (std::size_t f = 0; f < nf; ++f)
      for (std::size_t k = 0; k < 3; ++k)
        if (distinct(tri[f], k)) vf[static_cast<std::size_t>(fill[static_cast<std::size_t>(tri[f][k])]++)] = static_cast<int>(f);
  }
  // A column has at most 1 + 2 (faces) distinct rows: v and the other corners of its faces.
  std::vector<std::size_t> slot(nv + 1, 0);
  for (std::size_t v = 0; v < nv; ++v)
    slot[v + 1] = slot[v] + 1 + 2 * static_cast<std::size_t>(vf_start[v + 1] - vf_start[v]);
  std::vector<int> rows(slot[nv]);
  std::vector<double> vals(slot[nv]);
  std::vector<int> count(nv, 0);
  cancellation_point();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
    const CancellationScope::Join join(run);
    cancellation_point();
    for (std::size_t v = r.begin(); v != r.end(); ++v) {
      int* row = rows.data() + slot[v];
      double* val = vals.data() + slot[v];
      int n = 0;
      // First contribution sets the entry, later ones add to it: setFromTriplets' fold.
      const auto add = [&](int at, double value) {
        for (int e = 0; e < n; ++e)
          if (row[e] == at) {
            val[e] = val[e] + value;
            return;
          }
        row[n] = at;
        val[n++] = value;
      };
      const int iv = static_cast<int>(v);
      for (int q = vf_start[v]; q < vf_start[v + 1]; ++q) {
        const auto f = static_cast<std::size_t>(vf[static_cast<std::size_t>(q)]);
        for (std::size_t k = 0; k < 3; ++k) {
          if (!ok[3 * f + k]) continue;
          const int i = tri[f][k], j = tri[f][(k + 1) % 3];
          const double wk = w[3 * f + k];
          if (j == iv) add(i, -wk);  // (i, j, -w)
          if (i == iv) add(j, -wk);  // (j, i, -w)
          if (i == iv) add(i, wk);   // (i, i, w)
          if (j == iv) add(j, wk);   // (j, j, w)
        }
      }
      // Rows in increasing order, as the transposed copy leaves them (insertion sort: a handful).
      for (int a = 1; a < n; ++a)
        for (int b = a; b > 0 && row[b - 1] > row[b]; --b) {
          std::swap(row[b - 1], row[b]);
          std::swap(val[b - 1], val[b]);
        }
      count[v] = n;
    }
  });
  cancellation_point();
  const auto n = static_cast<Eigen::Index>(nv);
  Eigen::SparseMatrix<double> L(n, n);
  std::vector<std::size_t> start(nv + 1, 0);
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] = start[v] + static_cast<std::size_t>(count[v]);
  L.resizeNonZeros(static_cast<Eigen::Index>(start[nv]));
  int* outer = L.outerIndexPtr();
  int* inner = L.innerIndexPtr();
  double* value = L.valuePtr();
  for (std::size_t v = 0; v <= nv; ++v) outer[v] = static_cast<int>(start[v]);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t v = r.begin(); v != r.end(); ++v) {
      std::copy_n(rows.data() + slot[v], count[v], inner + start[v]);
      std::copy_n(vals.data() + slot[v], count[v], value + start[v]);
    }
  });
  return L;
}

}  // namespace shellcontract::detail
