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
#include <vector>

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

/// The two-level preconditioner of A = M + t L and the conjugate-gradient loop.
class TwoLevelSolver {
 public:
  TwoLevelSolver(const SpMat& A, const std::vector<int>& agg, const SpMat& coarse)
      : A_(A), agg_(agg), diag_(A.diagonal()), coarse_(coarse) {}

  bool ok() const { return coarse_.info() == Eigen::Success && (diag_.array() > 0.0).all(); }

  /// Solves A u = b to HEAT_ITERATIVE_TOLERANCE; the iteration count, or -1 when it does not
  /// converge.
  int solve(const Eigen::VectorXd& b, Eigen::VectorXd& u) const {
    const double target = HEAT_ITERATIVE_TOLERANCE * b.norm();
    u = Eigen::VectorXd::Zero(b.size());
    Eigen::VectorXd r = b;
    if (!(r.norm() > target)) return 0;
    Eigen::VectorXd z = precondition(r), p = z, Ap(b.size());
    double rz = r.dot(z);
    for (int it = 0; it < MAX_ITERATIONS; ++it) {
      Ap.noalias() = A_ * p;
      const double pAp = p.dot(Ap);
      if (!(pAp > 0.0)) return -1;
      const double alpha = rz / pAp;
      u += alpha * p;
      r -= alpha * Ap;
      if (r.norm() <= target) return it + 1;
      z = precondition(r);
      const double rz_next = r.dot(z);
      p = z + (rz_next / rz) * p;
      rz = rz_next;
    }
    return -1;
  }

 private:
  /// One symmetric cycle: forward sweep, coarse correction, backward sweep (so the
  /// preconditioner is symmetric positive definite, as conjugate gradients need).
  Eigen::VectorXd precondition(const Eigen::VectorXd& r) const {
    const Eigen::Index n = r.size();
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
    for (Eigen::Index i = 0; i < n; ++i) sweep(r, z, i);
    const Eigen::VectorXd residual = r - A_ * z;
    Eigen::VectorXd rc = Eigen::VectorXd::Zero(coarse_.rows());
    for (Eigen::Index i = 0; i < n; ++i) rc(agg_[static_cast<std::size_t>(i)]) += residual(i);
    const Eigen::VectorXd ec = coarse_.solve(rc);
    for (Eigen::Index i = 0; i < n; ++i) z(i) += ec(agg_[static_cast<std::size_t>(i)]);
    for (Eigen::Index i = n - 1; i >= 0; --i) sweep(r, z, i);
    return z;
  }

  /// Gauss-Seidel update of z_i (A is symmetric: column i is row i).
  void sweep(const Eigen::VectorXd& r, Eigen::VectorXd& z, Eigen::Index i) const {
    double s = r(i);
    for (SpMat::InnerIterator it(A_, i); it; ++it)
      if (it.row() != i) s -= it.value() * z(it.row());
    z(i) = s / diag_(i);
  }

  const SpMat& A_;
  const std::vector<int>& agg_;
  Eigen::VectorXd diag_;
  Ldlt coarse_;
};

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
  if (iterative) {
    agg = aggregate(L, count);
    SpMat P(n, count);
    entries.clear();
    for (Eigen::Index i = 0; i < n; ++i) entries.emplace_back(i, agg[static_cast<std::size_t>(i)], 1.0);
    P.setFromTriplets(entries.begin(), entries.end());
    const SpMat Pt = P.transpose();
    Mc = Pt * M * P;
    Lc = Pt * L * P;
  }
  // The times are independent systems: solved side by side (each solve is the same
  // deterministic sequence of operations as alone, so the result does not depend on the threads).
  std::vector<Eigen::VectorXd> out(times.size());
  std::vector<char> failed(times.size(), 0);
  std::vector<int> used(times.size(), 0);
  tbb::parallel_for(std::size_t{0}, times.size(), [&](std::size_t k) {
    const SpMat A = M + times[k] * L;
    if (iterative) {
      const TwoLevelSolver solver(A, agg, SpMat(Mc + times[k] * Lc));
      if (solver.ok() && (used[k] = solver.solve(rhs, out[k])) >= 0) return;
      used[k] = 0;
    }
    failed[k] = direct_solve(A, rhs, out[k]) ? 0 : 1;
  });
  if (std::any_of(failed.begin(), failed.end(), [](char f) { return f != 0; }))
    throw UsageError("select_spherical_regions: the smoothing system is singular");
  if (iterations) *iterations = used;
  return out;
}

}  // namespace shellcontract::detail
