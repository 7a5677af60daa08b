// Central finite differences of a scalar function of a small fixed-size matrix, with an eps sweep
// (HOBAK's convergenceTest habit: the best step of the sweep must reach the tolerance).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace shellcontract::test {

/// Central-difference gradient of f at X: G(i, j) = (f(X + h E_ij) - f(X - h E_ij)) / (2 h).
/// @param f  callable double(const Matrix&)
/// @param h  absolute step (same units as the entries of X)
template <class Matrix, class Fn>
Matrix fd_gradient(const Fn& f, const Matrix& X, double h) {
  Matrix G;
  G.resizeLike(X);
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    for (Eigen::Index j = 0; j < X.cols(); ++j) {
      Matrix Xp = X, Xm = X;
      Xp(i, j) += h;
      Xm(i, j) -= h;
      G(i, j) = (f(Xp) - f(Xm)) / (2.0 * h);
    }
  }
  return G;
}

/// Outcome of fd_sweep().
struct FdSweep {
  std::vector<double> steps;       ///< the steps h tried, largest first
  std::vector<double> rel_errors;  ///< |G - G_fd(h)|_F / |G|_F for each step
  double best_error = std::numeric_limits<double>::infinity();
  double best_step = 0.0;
  double analytic_norm = 0.0;  ///< |G|_F (callers require it to be nonzero)

  /// Human-readable table of the sweep, for failure messages.
  std::string report() const {
    std::ostringstream o;
    o << std::setprecision(3) << "|G| = " << analytic_norm << "; h: rel.err =";
    for (std::size_t k = 0; k < steps.size(); ++k) o << "  " << steps[k] << ": " << rel_errors[k];
    return o.str();
  }
};

/// The default steps: 1e-3 down to 1e-9 (entries of F are O(1) in the material tests).
inline std::vector<double> default_fd_steps() { return {1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9}; }

/// Compares an analytic gradient G of f at X with central differences for every step in `steps`,
/// relative to |G|_F. The caller checks best_error against its tolerance and analytic_norm > 0.
template <class Matrix, class Fn>
FdSweep fd_sweep(const Fn& f, const Matrix& X, const Matrix& G,
                 const std::vector<double>& steps = default_fd_steps()) {
  FdSweep out;
  out.analytic_norm = G.norm();
  for (double h : steps) {
    const Matrix Gfd = fd_gradient(f, X, h);
    const double err = (G - Gfd).norm() / out.analytic_norm;
    out.steps.push_back(h);
    out.rel_errors.push_back(err);
    if (err < out.best_error) {
      out.best_error = err;
      out.best_step = h;
    }
  }
  return out;
}

/// Full-precision text of a matrix, for SCOPED_TRACE (one row per line).
template <class Matrix>
std::string matrix_string(const Matrix& X) {
  std::ostringstream o;
  o << std::setprecision(17);
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    o << "[";
    for (Eigen::Index j = 0; j < X.cols(); ++j) o << (j ? ", " : "") << X(i, j);
    o << "]";
  }
  return o.str();
}

}  // namespace shellcontract::test
