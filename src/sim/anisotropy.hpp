// Anisotropic regions (paper section 3.3, math-spec 7): which faces carry E_A, their fibre
// directions in the rest frame, and k_A.
#pragma once

#include <cstddef>
#include <vector>

#include "pbd/constraints.hpp"
#include "shellcontract/mesh.hpp"
#include "shellcontract/simulation_options.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// What building the anisotropic constraints did, for the log.
struct AnisotropyReport {
  std::size_t faces = 0;            ///< faces with an E_A constraint
  std::size_t fallback_fibers = 0;  ///< faces where the direction was undefined: a = (1, 0)
};

/// Stores the fibre direction of every region face in the map "f:fiber_dir" (unit Vec2 in the
/// face's rest frame; (1, 0) outside the regions and on degenerate faces), then appends one E_A
/// constraint per non-degenerate region face to set.anisotropic (with the fibre read from that
/// map in ElementMaterialData::fiber) and its k_A to set.anisotropic_k_a. Constraints come
/// region by region, each region's faces in ascending order.
/// @pre build_rest_state(mesh) was called (reads f:triangle_rest); the regions are in
///      "f:region" (no map: no region)
AnisotropyReport add_anisotropic_constraints(Mesh& mesh, const AnisotropyOptions& options,
                                             ConstraintSet& set);

/// Unit fibre direction in a face's rest frame from a 3D direction d (math-spec 7):
/// normalize(d . T1, d . T2), or (1, 0) when that 2-vector is shorter than 1e-3 |d|.
/// @param fallback  set to true when the fallback was taken
Vec2 fiber_in_rest_frame(const Vec3& d, const Vec3& T1, const Vec3& T2, bool& fallback);

}  // namespace shellcontract
