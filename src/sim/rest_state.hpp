// Rest state (architecture.md data flow): property maps built once on the normalized input mesh,
// then packed into the solver's flat constraint arrays.
#pragma once

#include <cstddef>

#include <Eigen/Core>

#include "pbd/constraints.hpp"
#include "shellcontract/mesh.hpp"
#include "shellcontract/simulation_options.hpp"

namespace shellcontract {

/// What building the rest state skipped (math-spec 11), for the log.
struct RestStateReport {
  std::size_t degenerate_faces = 0;    ///< faces with no membrane constraint
  std::size_t inactive_hinges = 0;     ///< hinges touching a degenerate face
  std::size_t clamped_cotangents = 0;  ///< rest cotangents clamped to +-cot(1 degree)
  /// Faces, not degenerate, with a rest angle below 1 degree (math-spec 11: slivers, whose
  /// membrane is stiff under XPBD), whatever the bending model.
  std::size_t sliver_faces = 0;
};

/// Attaches f:triangle_rest, e:hinge, e:isometric_bending, e:dihedral_bending and v:inv_mass
/// (mesh/properties.hpp) computed from the mesh points.
/// @pre closed triangle mesh, !mesh.has_garbage(), rest state not yet built
RestStateReport build_rest_state(Mesh& mesh, MassModel mass, double density);

/// Packs the constraints of the options' bending model from the property maps, in face and
/// edge index order. Degenerate faces and the hinges that touch them are left out.
ConstraintSet pack_constraints(const Mesh& mesh, BendingModel bending);

/// The v:inv_mass map as a vector indexed by vertex index.
Eigen::VectorXd inverse_masses(const Mesh& mesh);

/// Faces as a #F by 3 array in face index order. @pre triangle mesh without garbage
Faces faces_array(const Mesh& mesh);

}  // namespace shellcontract
