// The constraint solver: nonlinear Gauss-Seidel over every constraint in a fixed order
// (paper Steps 3-5, math-spec 2 step 2 and 9.4), in PBD or XPBD mode.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include <Eigen/Core>

#include "material/registry.hpp"
#include "pbd/constraints.hpp"
#include "shellcontract/material.hpp"
#include "shellcontract/observer.hpp"
#include "shellcontract/simulation_options.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// Number of colours of each constraint kind (all 0 in the Sequential order).
struct ColourCounts {
  int membrane = 0;
  int isometric = 0;
  int dihedral = 0;
  int anisotropic = 0;
  /// Coloured order in the regional layout: the interiors of two vertex-id ranges run in
  /// parallel, then the interface constraints (see solver.cpp, REGIONS). Used when every
  /// constraint is a StVK membrane or an isometric hinge and few span the two ranges.
  bool regional = false;
};

/// Projects all constraints of a scene. Built by make_constraint_solver.
class ConstraintSolver {
 public:
  virtual ~ConstraintSolver() = default;

  /// Runs settings.iterations sweeps (membranes, isometric hinges, dihedral hinges,
  /// anisotropic faces; each in array order, or colour by colour in the Coloured order),
  /// updating x in place. XPBD multipliers start at 0. Allocates nothing (after the first call).
  /// @param x         #V by 3 positions (normalized units), predicted positions on entry
  /// @param inv_mass  #V inverse masses (0 = pinned)
  virtual void solve(Positions& x, const Eigen::VectorXd& inv_mass) = 0;

  /// Energies of every constraint kind at x (no projection).
  virtual ConstraintEnergies energies(const Positions& x) const = 0;

  /// Membrane plus anisotropic elastic energy of every face at x (0 for faces without a
  /// constraint), indexed by MembraneConstraint::face.
  /// @param num_faces  #F of the mesh
  virtual Eigen::VectorXd face_energies(const Positions& x, Eigen::Index num_faces) const = 0;

  /// The constraints being projected, in sweep order (grouped by colour in the Coloured order;
  /// MembraneConstraint::face still names each face).
  virtual const ConstraintSet& constraints() const = 0;

  /// Colours used per constraint kind (Coloured order; zeros for Sequential).
  virtual ColourCounts colour_counts() const = 0;

  /// Gives face's membrane a new rest shape (Dm^-1 as triangle_rest makes it, and the rest area)
  /// for the solves and energies from now on; its step clamp and mass stay. The anisotropic
  /// records keep theirs.
  /// @return false when the face has no membrane record (degenerate at rest)
  virtual bool set_membrane_rest(int face, const Mat2& Dm_inv, double rest_area) = 0;

  /// Sets the rest angle of constraints().dihedral_hinges[record] (kappa_bar kept).
  virtual void set_dihedral_rest_angle(std::size_t record, double rest_angle) = 0;
};

/// Builds a solver for the given membrane material and the anisotropic energy of
/// settings.aniso. Constraints with degenerate rest data must already be excluded from the set.
/// @param faces  #F by 3 faces (for the vertex normals of the inversion-aware mode)
/// @throws std::invalid_argument if settings.threads < 0
std::unique_ptr<ConstraintSolver> make_constraint_solver(MaterialKind material,
                                                         const MaterialParams& params,
                                                         ConstraintSet constraints,
                                                         const SolverSettings& settings,
                                                         const Faces& faces = Faces());

}  // namespace shellcontract
