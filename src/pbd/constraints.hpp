// Flat per-constraint records the solver iterates over (one contiguous array per kind).
// They are packed once from the rest-state property maps (sim/rest_state) and hold only what a
// projection reads, so a sweep streams through memory.
#pragma once

#include <algorithm>
#include <array>
#include <vector>

#include "bending/dihedral_bending.hpp"
#include "shellcontract/material.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// Membrane (E_S) constraint of one non-degenerate face (math-spec 4, 9.1).
struct MembraneConstraint {
  std::array<int, 3> v;  ///< vertex ids (j1, j2, j3), counter-clockwise from outside
  Mat2 Dm_inv;           ///< rest Dm^-1 (math-spec 4.1)
  double rest_area;      ///< Abar
  double max_step;       ///< PBD step clamp beta_max * shortest rest edge (math-spec 9.1d)
  ElementMaterialData data;  ///< fibre direction (anisotropic energies only)
  int face = -1;             ///< mesh face index (for per-face output)
};

/// The solver's compact copy of a MembraneConstraint (56 bytes instead of 88): what one
/// projection reads, contiguous, in sweep order. Dm^-1 is upper triangular because the rest
/// frame puts edge j1 - j3 on the first axis (math-spec 4.1), so 3 doubles hold it. The fibre
/// direction lives in a side array, only for anisotropic faces.
struct PackedMembrane {
  std::array<int, 3> v;  ///< vertex ids (j1, j2, j3)
  int face;              ///< mesh face index (kept so the record is 8-byte aligned anyway)
  double dm00, dm01, dm11;  ///< Dm^-1 = [[dm00, dm01], [0, dm11]]
  double rest_area;         ///< Abar
  double max_step;          ///< PBD step clamp (math-spec 9.1d)
};

/// Packs c. \pre c.Dm_inv(1, 0) == 0 (as triangle_rest makes it); that entry is not stored.
inline PackedMembrane pack_membrane(const MembraneConstraint& c) {
  return PackedMembrane{c.v, c.face, c.Dm_inv(0, 0), c.Dm_inv(0, 1), c.Dm_inv(1, 1), c.rest_area,
                        c.max_step};
}

/// Isometric bending hinge (math-spec 8.2). Stencil order of bending/hinge.hpp.
struct IsometricHingeConstraint {
  std::array<int, 4> v;
  Eigen::Vector4d K;      ///< rest cotangent weights
  double three_over_area; ///< 3 / (A0 + A1), rest areas
  double max_step;        ///< beta_max * shortest rest edge of the stencil
};

/// Rest-aware dihedral hinge (math-spec 8.3).
struct DihedralHingeConstraint {
  std::array<int, 4> v;
  DihedralBendingRest rest;
  double max_step;
};

/// Every constraint of a scene, in the fixed Gauss-Seidel order of math-spec 9.4
/// (membranes, then hinges, then anisotropic faces).
struct ConstraintSet {
  std::vector<MembraneConstraint> membranes;
  std::vector<IsometricHingeConstraint> isometric_hinges;
  std::vector<DihedralHingeConstraint> dihedral_hinges;
  std::vector<MembraneConstraint> anisotropic;  ///< E_A faces of the selected regions (math-spec 7)
  /// k_A of each anisotropic face (force units, math-spec 9.3), same order as `anisotropic`;
  /// used only by the paper's in-projection inward term.
  std::vector<double> anisotropic_k_a;
};

/// One more than the largest vertex id any constraint of `set` names (0 for an empty set).
inline int vertex_count(const ConstraintSet& set) {
  int n = 0;
  const auto grow = [&n](const auto& records) {
    for (const auto& c : records)
      for (int v : c.v) n = std::max(n, v + 1);
  };
  grow(set.membranes);
  grow(set.isometric_hinges);
  grow(set.dihedral_hinges);
  grow(set.anisotropic);
  return n;
}

/// beta_max of the PBD step clamp (math-spec 9.1d, 14).
inline constexpr double STEP_CLAMP_FACTOR = 0.2;

}  // namespace shellcontract
