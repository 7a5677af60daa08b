// The region finder's heat solves (heat_smoothing.hpp). The iterative one is conjugate gradients
// preconditioned by a symmetric two-level cycle: a forward Gauss-Seidel sweep, an exact solve on
// aggregates of neighbouring vertices (piecewise-constant prolongation), a backward sweep. The
// sweeps remove the rough error and the aggregates the smooth error a sweep barely touches, so
// the iteration count does not grow with the mesh's resolution as plain (Jacobi) CG's does.
#include "geometry/heat_smoothing.hpp"

#include <Eigen/SparseCholesky>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/cancellation.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract::detail {
namespace {

using SpMat = Eigen::SparseMatrix<double>;
using Ldlt = Eigen::SimplicialLDLT<SpMat>;

/// Beyond this many iterations the system is not what the preconditioner expects (its count
/// does not grow with the resolution and stays far below this on meshes): the direct solver is
/// used instead.
constexpr int MAX_ITERATIONS = 400;

/// Aggregates in index order: a vertex whose neighbours are all free takes them; each vertex
/// left over joins the aggregate of its neighbour with the smallest aggregate id. Deterministic
/// for a given vertex order. Returns the aggregate of each vertex and sets count.
std::vector<int> aggregate(const SpMat& L, int& count) {
  const auto n = static_cast<std::size_t>(L.cols());
  std::vector<int> agg(n, -1);
  count = 0;
  for (Eigen::Index v = 0; v < L.cols(); ++v) {
    if (agg[static_cast<std::size_t>(v)] >= 0) continue;
    bool free = true;
    for (SpMat::InnerIterator it(L, v); it && free; ++it) free = it.row() == v || agg[static_cast<std::size_t>(it.row())] < 0;
    if (!free) continue;
    for (SpMat::InnerIterator it(L, v); it; ++it) agg[static_cast<std::size_t>(it.row())] = count;
    agg[static_cast<std::size_t>(v)] = count++;
  }
  const std::vector<int> first = agg;  // pass-one aggregates only: the leftovers' order cannot matter
  for (Eigen::Index v = 0; v < L.cols(); ++v) {
    if (agg[static_cast<std::size_t>(v)] >= 0) continue;
    int best = -1;
    for (SpMat::InnerIterator it(L, v); it; ++it) {
      const int a = first[static_cast<std::size_t>(it.row())];
      if (a >= 0 && (best < 0 || a < best)) best = a;
    }
    agg[static_cast<std::size_t>(v)] = best >= 0 ? best : count++;
  }
  return agg;
}

/// The sparsity pattern the systems M + t L share (compressed columns; A is symmetric, so a
/// column is also a row), with the position of each diagonal entry.
struct Pattern {
  Eigen::Index n = 0;
  const int* outer = nullptr;
  const int* inner = nullptr;
  std::vector<int> diag;  ///< index of (i, i) in inner; -1 when absent
  /// L's value at each entry (0 where only M has one). An off-diagonal entry of M + t L is
  /// 0 + t L_ij, as Eigen's sum computes it: formed on the fly, so that the systems of a
  /// batch read one array of values instead of one each (the sweeps wait on memory).
  std::vector<double> lval;
  /// Each column's rows strictly increasing and lval(i, j) == lval(j, i) for every entry: the
  /// products can be gathered by rows (multiply_add).
  bool symmetric = false;
};

/// One system A u = b of the batch: its time (A = M + t L on the shared pattern), its diagonal, the
/// coarse factor, and the conjugate-gradient state.
struct System {
  double t = 0.0;
  Eigen::VectorXd diag;
  Ldlt coarse;
  Eigen::VectorXd u, r, z, p, Ap, residual;
  double target = 0.0, rz = 0.0;
  int iterations = 0;
  bool solved = false;  ///< converged (iterations: how many it took, 0 when b was already 0)
};

/// The kernels below run K systems side by side, each with exactly the operations (and their
/// order) it would have alone: the rows' sums are chains of dependent additions that leave the
/// processor idle, and K independent chains fill it. Each system's sums keep Eigen's order (the
/// sparse-times-vector product adds column by column), so a system's result does not depend on
/// the batch it ran in.
template <int K>
void forward_sweep(const Pattern& a, System* const* s) {
  for (Eigen::Index i = 0; i < a.n; ++i) {
    double acc[K];
    for (int k = 0; k < K; ++k) acc[k] = s[k]->r(i);
    // z starts at 0 and the sweep goes up: only the entries above the diagonal (rows < i)
    // multiply a non-zero z.
    for (int e = a.outer[i]; e < a.diag[static_cast<std::size_t>(i)]; ++e) {
      const int row = a.inner[e];
      const double l = a.lval[e];
      for (int k = 0; k < K; ++k) acc[k] -= (0.0 + s[k]->t * l) * s[k]->z(row);
    }
    for (int k = 0; k < K; ++k) s[k]->z(i) = acc[k] / s[k]->diag(i);
  }
}

template <int K>
void backward_sweep(const Pattern& a, System* const* s) {
  for (Eigen::Index i = a.n - 1; i >= 0; --i) {
    double acc[K];
    for (int k = 0; k < K; ++k) acc[k] = s[k]->r(i);
    const int d = a.diag[static_cast<std::size_t>(i)];
    for (int e = a.outer[i]; e < a.outer[i + 1]; ++e) {
      if (e == d) continue;
      const int row = a.inner[e];
      const double l = a.lval[e];
      for (int k = 0; k < K; ++k) acc[k] -= (0.0 + s[k]->t * l) * s[k]->z(row);
    }
    for (int k = 0; k < K; ++k) s[k]->z(i) = acc[k] / s[k]->diag(i);
  }
}

/// out_k = start_k + sign * A_k x_k. Eigen's y = A x (sign +1, start 0) and y = r - A x (sign
/// -1, start r) add column by column, so row i receives its terms in increasing column j. On a
/// pattern whose values are symmetric bit for bit (Pattern::symmetric) row i's terms are
/// column i's entries in increasing row: gathered row by row here, with the same products
/// added in the same order (the same bits), one accumulator per row instead of scattered
/// read-modify-writes (lab/regions/speed.md). Otherwise the column-by-column scatter.
template <int K>
void multiply_add(const Pattern& a, System* const* s, Eigen::VectorXd System::*out, const Eigen::VectorXd System::*x,
                  double sign) {
  if (a.symmetric) {
    for (Eigen::Index i = 0; i < a.n; ++i) {
      double acc[K];
      for (int k = 0; k < K; ++k) acc[k] = (s[k]->*out)(i);
      const int d = a.diag[static_cast<std::size_t>(i)];
      for (int e = a.outer[i]; e < a.outer[i + 1]; ++e) {
        const int col = a.inner[e];
        const double l = a.lval[e];
        if (e == d)
          for (int k = 0; k < K; ++k) acc[k] += s[k]->diag(i) * (sign * (s[k]->*x)(col));
        else
          for (int k = 0; k < K; ++k) acc[k] += (0.0 + s[k]->t * l) * (sign * (s[k]->*x)(col));
      }
      for (int k = 0; k < K; ++k) (s[k]->*out)(i) = acc[k];
    }
    return;
  }
  for (Eigen::Index j = 0; j < a.n; ++j) {
    double xj[K];
    for (int k = 0; k < K; ++k) xj[k] = sign * (s[k]->*x)(j);
    const int d = a.diag[static_cast<std::size_t>(j)];
    for (int e = a.outer[j]; e < a.outer[j + 1]; ++e) {
      const int row = a.inner[e];
      const double l = a.lval[e];
      if (e == d)
        for (int k = 0; k < K; ++k) (s[k]->*out)(row) += s[k]->diag(row) * xj[k];
      else
        for (int k = 0; k < K; ++k) (s[k]->*out)(row) += (0.0 + s[k]->t * l) * xj[k];
    }
  }
}

/// The two-level preconditioner and the conjugate-gradient loop of a batch of systems.
class TwoLevelBatch {
 public:
  TwoLevelBatch(const Pattern& a, const std::vector<int>& agg, std::vector<System*> systems)
      : a_(a), agg_(agg), systems_(std::move(systems)) {}

  /// Solves each A u = b to HEAT_ITERATIVE_TOLERANCE; a system marked solved holds u and its
  /// iteration count, the others did not converge.
  void solve(const Eigen::VectorXd& b) {
    std::vector<System*> active;
    for (System* s : systems_) {
      s->target = HEAT_ITERATIVE_TOLERANCE * b.norm();
      s->u = Eigen::VectorXd::Zero(b.size());
      s->r = b;
      s->iterations = 0;
      s->solved = !(s->r.norm() > s->target);
      if (!s->solved) active.push_back(s);
    }
    precondition(active);
    for (System* s : active) {
      s->p = s->z;
      s->rz = s->r.dot(s->z);
      s->Ap.resize(b.size());
    }
    for (int it = 0; it < MAX_ITERATIONS && !active.empty(); ++it) {
      // The longest stage of a large mesh's region selection: a run's cancel is heard here.
      cancellation_point();
      for (System* s : active) s->Ap.setZero();
      run(active, [&](System* const* s, auto k) { multiply_add<decltype(k)::value>(a_, s, &System::Ap, &System::p, 1.0); });
      std::vector<System*> next;
      for (System* s : active) {
        const double pAp = s->p.dot(s->Ap);
        if (!(pAp > 0.0)) continue;  // not positive definite: the direct solver takes it
        const double alpha = s->rz / pAp;
        s->u += alpha * s->p;
        s->r -= alpha * s->Ap;
        if (s->r.norm() <= s->target) {
          s->iterations = it + 1;
          s->solved = true;
          continue;
        }
        next.push_back(s);
      }
      active = std::move(next);
      precondition(active);
      for (System* s : active) {
        const double rz_next = s->r.dot(s->z);
        s->p = s->z + (rz_next / s->rz) * s->p;
        s->rz = rz_next;
      }
    }
  }

 private:
  /// Calls f(systems, std::integral_constant<int, K>) on the active systems, two at a time.
  template <typename F>
  static void run(const std::vector<System*>& active, F&& f) {
    std::size_t i = 0;
    for (; i + 2 <= active.size(); i += 2) f(active.data() + i, std::integral_constant<int, 2>{});
    if (i < active.size()) f(active.data() + i, std::integral_constant<int, 1>{});
  }

  /// One symmetric cycle on each system's r into its z: forward sweep, coarse correction,
  /// backward sweep (so the preconditioner is symmetric positive definite, as conjugate
  /// gradients need).
  void precondition(const std::vector<System*>& active) const {
    for (System* s : active) {
      s->z = Eigen::VectorXd::Zero(s->r.size());
      s->residual = s->r;
    }
    run(active, [&](System* const* s, auto k) { forward_sweep<decltype(k)::value>(a_, s); });
    run(active, [&](System* const* s, auto k) { multiply_add<decltype(k)::value>(a_, s, &System::residual, &System::z, -1.0); });
    for (System* s : active) {
      Eigen::VectorXd rc = Eigen::VectorXd::Zero(s->coarse.rows());
      for (Eigen::Index i = 0; i < a_.n; ++i) rc(agg_[static_cast<std::size_t>(i)]) += s->residual(i);
      const Eigen::VectorXd ec = s->coarse.solve(rc);
      for (Eigen::Index i = 0; i < a_.n; ++i) s->z(i) += ec(agg_[static_cast<std::size_t>(i)]);
    }
    run(active, [&](System* const* s, auto k) { backward_sweep<decltype(k)::value>(a_, s); });
  }

  const Pattern& a_;
  const std::vector<int>& agg_;
  std::vector<System*> systems_;
};

/// Whether the pattern's columns are sorted and its L values symmetric (Pattern::symmetric).
bool symmetric_values(const Pattern& a) {
  for (Eigen::Index i = 0; i < a.n; ++i)
    for (int e = a.outer[i] + 1; e < a.outer[i + 1]; ++e)
      if (!(a.inner[e - 1] < a.inner[e])) return false;
  for (Eigen::Index i = 0; i < a.n; ++i)
    for (int e = a.outer[i]; e < a.outer[i + 1]; ++e) {
      const int j = a.inner[e];
      const int* begin = a.inner + a.outer[j];
      const int* end = a.inner + a.outer[j + 1];
      const int* at = std::lower_bound(begin, end, static_cast<int>(i));
      if (at == end || *at != i || !(a.lval[static_cast<std::size_t>(at - a.inner)] == a.lval[static_cast<std::size_t>(e)]))
        return false;
    }
  return true;
}

bool direct_solve(const SpMat& A, const Eigen::VectorXd& rhs, Eigen::VectorXd& u) {
  const Ldlt solver(A);
  if (solver.info() != Eigen::Success) return false;
  u = solver.solve(rhs);
  return true;
}

}  // namespace

std::vector<Eigen::VectorXd> heat_solves(const SpMat& L, const Eigen::VectorXd& mass, const Eigen::VectorXd& rhs,
                                         const std::vector<double>& times, bool iterative,
                                         std::vector<int>* iterations) {
  const Eigen::Index n = L.rows();
  SpMat M(n, n);
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) entries.emplace_back(i, i, mass(i));
  M.setFromTriplets(entries.begin(), entries.end());
  // The coarse space is shared by every time: P^T M P + t P^T L P.
  int count = 0;
  std::vector<int> agg;
  SpMat Mc, Lc;
  // A run's cancel between the set-up's passes, each a single long call on a large mesh.
  cancellation_point();
  if (iterative) {
    agg = aggregate(L, count);
    cancellation_point();
    SpMat P(n, count);
    entries.clear();
    for (Eigen::Index i = 0; i < n; ++i) entries.emplace_back(i, agg[static_cast<std::size_t>(i)], 1.0);
    P.setFromTriplets(entries.begin(), entries.end());
    const SpMat Pt = P.transpose();
    Mc = Pt * M * P;
    Lc = Pt * L * P;
    cancellation_point();
  }
  std::vector<Eigen::VectorXd> out(times.size());
  std::vector<char> failed(times.size(), 0);
  std::vector<int> used(times.size(), 0);
  // Every A_k = M + t_k L has the pattern of M + L (M's diagonal is all there).
  std::vector<SpMat> A(times.size());
  tbb::parallel_for(std::size_t{0}, times.size(), [&](std::size_t k) {
    A[k] = M + times[k] * L;
    A[k].makeCompressed();
  });
  cancellation_point();
  Pattern pattern;
  bool shared = iterative && !A.empty();
  if (shared) {
    pattern.n = n;
    pattern.outer = A[0].outerIndexPtr();
    pattern.inner = A[0].innerIndexPtr();
    pattern.diag.assign(static_cast<std::size_t>(n), -1);
    for (Eigen::Index i = 0; i < n; ++i)
      for (int e = pattern.outer[i]; e < pattern.outer[i + 1]; ++e)
        if (pattern.inner[e] == i) pattern.diag[static_cast<std::size_t>(i)] = e;
    shared = std::all_of(pattern.diag.begin(), pattern.diag.end(), [](int d) { return d >= 0; });
    // L's values on A's pattern (L's entries are a subset of it: M adds only the diagonal).
    pattern.lval.assign(static_cast<std::size_t>(A[0].nonZeros()), 0.0);
    for (Eigen::Index i = 0; i < n && shared; ++i) {
      int e = pattern.outer[i];
      for (SpMat::InnerIterator it(L, i); it; ++it) {
        while (e < pattern.outer[i + 1] && pattern.inner[e] < it.row()) ++e;
        shared = shared && e < pattern.outer[i + 1] && pattern.inner[e] == it.row();
        if (shared) pattern.lval[static_cast<std::size_t>(e)] = it.value();
      }
    }
    pattern.symmetric = shared && symmetric_values(pattern);
    for (const SpMat& a : A)
      shared = shared && a.nonZeros() == A[0].nonZeros() &&
               std::equal(pattern.outer, pattern.outer + n + 1, a.outerIndexPtr()) &&
               std::equal(pattern.inner, pattern.inner + A[0].nonZeros(), a.innerIndexPtr());
  }
  std::vector<System> systems(times.size());
  if (shared) {
    // Two systems per batch, the shortest time with the longest (their iteration counts sum
    // to about the same), the batches side by side: each system's arithmetic is the same
    // whatever the batches and the threads.
    std::vector<std::vector<std::size_t>> batches;
    for (std::size_t lo = 0, hi = times.size(); lo < hi; ++lo) {
      --hi;
      batches.push_back(lo < hi ? std::vector<std::size_t>{lo, hi} : std::vector<std::size_t>{lo});
    }
    // The batches may run on worker threads: they stop too once the run's thread saw a cancel.
    const CancellationScope* const run = CancellationScope::current();
    tbb::parallel_for(std::size_t{0}, batches.size(), [&](std::size_t b) {
      const CancellationScope::Join join(run);
      std::vector<System*> members;
      for (std::size_t k : batches[b]) {
        System& s = systems[k];
        s.t = times[k];
        s.diag = A[k].diagonal();
        s.coarse.compute(SpMat(Mc + times[k] * Lc));
        if (s.coarse.info() == Eigen::Success && (s.diag.array() > 0.0).all()) members.push_back(&s);
      }
      TwoLevelBatch(pattern, agg, members).solve(rhs);
    });
  }
  // Each factorization is one call that cannot be interrupted, and below
  // HEAT_DIRECT_MAX_VERTICES the four of them are nearly all of the selection's time: a cancel
  // is heard before each (on a worker once the caller's thread has seen it), not only after all.
  const CancellationScope* const caller = CancellationScope::current();
  tbb::parallel_for(std::size_t{0}, times.size(), [&](std::size_t k) {
    if (systems[k].solved) {
      used[k] = systems[k].iterations;
      out[k] = std::move(systems[k].u);
      return;
    }
    const CancellationScope::Join join(caller);
    cancellation_point();
    failed[k] = direct_solve(A[k], rhs, out[k]) ? 0 : 1;
  });
  if (std::any_of(failed.begin(), failed.end(), [](char f) { return f != 0; }))
    // Singular only where the masses or the Laplacian are degenerate: the input's geometry.
    throw InputError("region selection: the mesh's heat smoothing system is singular "
                     "(triangles of zero or near-zero area?)");
  if (iterations) *iterations = used;
  return out;
}

}  // namespace shellcontract::detail
