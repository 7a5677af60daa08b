#pragma once
// Energies of membrane constraints at positions x, per face and summed (private to src/pbd):
// what ConstraintSolver::energies and face_energies report for the isotropic membranes and the
// anisotropic faces.

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "fem/triangle_element.hpp"
#include "pbd/constraint_kernels.hpp"
#include "pbd/constraints.hpp"

namespace shellcontract::solver_energies {

inline Vec3 row(const Positions& x, int i) { return Vec3(x(i, 0), x(i, 1), x(i, 2)); }

/// Adds each constraint's energy rest_area * psi(F) to e(face); constraints without a face in e,
/// collapsed triangles and (for frame-dependent models) irregular frames add nothing.
template <class Model>
inline void add_face_energies(const Model& m, const std::vector<MembraneConstraint>& set,
                              const Positions& x, const std::vector<double>* orientation,
                              Eigen::VectorXd& e) {
  for (std::size_t i = 0; i < set.size(); ++i) {
    const MembraneConstraint& c = set[i];
    if (c.face < 0 || c.face >= e.size()) continue;
    TriangleFrame fr;
    const double s = orientation ? (*orientation)[i] : 1.0;
    if (!triangle_frame(row(x, c.v[0]), row(x, c.v[1]), row(x, c.v[2]), c.Dm_inv, c.rest_area, s, fr))
      continue;
    if (!fr.regular && m.frame_dependent()) continue;
    e(c.face) += c.rest_area * m.psi(fr.F, c.data);
  }
}

/// The sum of the same energies over the constraints.
template <class Model>
inline double membrane_energy(const Model& m, const std::vector<MembraneConstraint>& set,
                              const Positions& x, const std::vector<double>* orientation) {
  double sum = 0.0;
  for (std::size_t i = 0; i < set.size(); ++i) {
    const MembraneConstraint& c = set[i];
    TriangleFrame fr;
    const double s = orientation ? (*orientation)[i] : 1.0;
    if (!triangle_frame(row(x, c.v[0]), row(x, c.v[1]), row(x, c.v[2]), c.Dm_inv, c.rest_area, s, fr))
      continue;
    if (!fr.regular && m.frame_dependent()) continue;
    sum += c.rest_area * m.psi(fr.F, c.data);
  }
  return sum;
}

}  // namespace shellcontract::solver_energies
