// Private to the region finder: the implicit heat step (M + t L) u = M h at several times t,
// solved directly on small meshes and by a two-level preconditioned conjugate gradient on large
// ones (a sparse Cholesky factor of a surface mesh grows like n^1.5 in work and is the finder's
// bottleneck there; the iterative solve is linear in n per iteration with a bounded count).
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace shellcontract::detail {

/// Vertex count from which the iterative solver is used. Below it the sparse LDLT factor is
/// cheap, and small meshes (the goldens, the tests) keep the direct solver's exact arithmetic.
constexpr long HEAT_DIRECT_MAX_VERTICES = 100000;

/// Relative residual |M h - (M + t L) u| / |M h| the iterative solver stops at: far below the
/// differences the finder compares (curvature maxima, signs), so it picks what the direct
/// solver picks.
constexpr double HEAT_ITERATIVE_TOLERANCE = 1e-12;

/// u_k = (M + t_k L)^{-1} rhs for every t_k; L symmetric positive semidefinite (both triangles
/// stored), M diagonal positive (as a vector). Each solve is one deterministic sequence of
/// operations whatever the threads. Throws InputError when a system is singular. When
/// iterative, a system the iteration does not solve within its bound is solved directly;
/// iterations (when given) receives each system's iteration count, 0 for a direct solve.
std::vector<Eigen::VectorXd> heat_solves(const Eigen::SparseMatrix<double>& L, const Eigen::VectorXd& mass,
                                         const Eigen::VectorXd& rhs, const std::vector<double>& times,
                                         bool iterative, std::vector<int>* iterations = nullptr);

}  // namespace shellcontract::detail
