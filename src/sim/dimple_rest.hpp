// The rest state of a mirrored dimple (docs/math/region-mirror.md, section 6): the local
// contraction changes the region's rest shape, not only where its vertices are put.
#pragma once

#include <cstddef>
#include <vector>

#include "pbd/solver.hpp"
#include "shellcontract/types.hpp"
#include "sim/region_dimple.hpp"
#include "sim/region_mirror.hpp"

namespace shellcontract {

/// The solver's dihedral hinges by the face edges they lie on, with the rest angles they were
/// built with, and the region of each face. Tables indexed by 3 f + e (edge e of face f runs from
/// corner e to corner e + 1): set_dimple_rest visits every edge of a dimple each time its size
/// changes, and a lookup there must not search.
struct HingeIndex {
  HingeIndex() = default;
  /// @param regions  the faces of each region
  HingeIndex(const std::vector<DihedralHingeConstraint>& hinges, const Faces& mesh_faces,
             const std::vector<std::vector<int>>& regions);
  /// [3 f + e]: the hinge record on that edge (the first one built there), -1: none
  std::vector<int> record_of_face_edge;
  /// [3 f + e]: the other face on that edge (-1: none). Of an edge with more than two faces, the
  /// first face sees the last, every other face the first.
  std::vector<int> face_across;
  std::vector<double> built_angle;  ///< per record
  std::vector<int> region_of_face;  ///< -1: none
};

/// What set_dimple_rest changed for one dimple (so the next call can undo it).
struct DimpleRestChange {
  std::vector<int> faces;           ///< faces whose membranes have a dimpled rest shape
  std::vector<std::size_t> hinges;  ///< hinge records with a dimpled rest angle
  /// Scratch of set_dimple_rest, all 0 between calls: per face and per hinge record, whether
  /// this call set it (an edge inside the dimple is met from both its faces; what the last call
  /// set and this one sets again needs no putting back).
  std::vector<char> face_set, hinge_set;
  /// Scratch, all -1 between calls: per vertex, its index in the dimple's vertices.
  std::vector<int> dimple_slot;
};

/// Gives d's current dimple (its first d.size faces of d.order) the rest state it has on its
/// mirror image at rest: each interior vertex of the dimple (crease ring included) at its image,
/// each rim vertex, and every vertex outside the dimple, where it is at rest. The dimple's
/// membranes take their triangles' shape there (a degenerate one keeps its own) and the dihedral
/// hinges on the dimple's edges their angle there (the rim's fold included), except a rim hinge
/// whose other face is in another region: two dimples would both set it, and its angle would
/// depend on which of them changed size last (a resumed run would not be the run). What `change`
/// records (the last call's) and this call does not set again is put back, so that a dimple that
/// shrinks or has no mirror (make_region_mirror's fallback) leaves nothing behind; `change`
/// becomes this call's.
/// @param rest        the rest positions the solver was built from
/// @param mesh_faces  #F by 3, the mesh's faces
/// @param mirror      make_region_mirror(rest, d.dimple), which the caller keeps for the dimple
void set_dimple_rest(ConstraintSolver& solver, const HingeIndex& hinges, const Positions& rest,
                     const Faces& mesh_faces, const RegionDimple& d, const RegionMirror& mirror,
                     DimpleRestChange& change);

/// The same, making d's mirror.
void set_dimple_rest(ConstraintSolver& solver, const HingeIndex& hinges, const Positions& rest,
                     const Faces& mesh_faces, const RegionDimple& d, DimpleRestChange& change);

}  // namespace shellcontract
