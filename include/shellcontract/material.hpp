// The one membrane-material interface: 2x2 in-plane deformation gradient in, energy density
// and first Piola-Kirchhoff stress out (HOBAK's HYPERELASTIC, reduced to membranes).
//
// Frame convention (math-spec 4.2-4.4): Fbar = p F is the 2x2 deformation gradient expressed in
// the current edge-aligned frame p = [t1; t2] of the triangle, with t1 along x_{j1} - x_{j3}.
// Fbar is upper triangular and det(Fbar) = s A / Abar, where s = +1 by default and s = -1 for a
// triangle the inversion-aware mode counts as inverted. The element (fem/triangle_element.hpp)
// lifts the 2x2 PK1 to 3D with P3 = p^T Pbar and applies the chain rule; a material never sees
// positions, areas or the mesh.
//
// Energies are densities per unit REST area (E = Abar * psi), math-spec 4.1.
// Every concrete model is a `final` class whose methods are defined inline in its header: the
// PBD solver is templated on the concrete type, so the per-element calls are devirtualized and
// inlined in the hot loop. Virtual calls are for tests and tools.
#pragma once

#include <string>

#include "shellcontract/simulation_options.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// Per-element data a material may read. Isotropic models ignore it.
struct ElementMaterialData {
  /// Unit fibre direction a in the face's REST frame (Tbar1, Tbar2) (math-spec 7).
  Vec2 fiber = Vec2(1.0, 0.0);
};

/// Plane-stress membrane Lame parameters from 3D Young's modulus E, Poisson ratio nu and
/// thickness h (math-spec 6): mu = E h / (2 (1 + nu)), lambda = E h nu / (1 - nu^2).
/// \pre E > 0, h > 0, -1 < nu < 1 (throws UsageError otherwise)
MaterialParams membrane_lame_from_young(double young, double poisson, double thickness);

/// The k_B at which the rest-aware dihedral bending energy (bending/dihedral_bending.hpp,
/// k_B kappa_bar (theta - theta_bar)^2) is a plate's bending energy, (D / 2) kappa^2 per unit
/// area with D = E h^3 / (12 (1 - nu^2)), for a cylindrical bend of a regularly triangulated
/// sheet: D / 3, because the hinge sum with k_B = 1 is 3 / 2 kappa^2 per unit area there (the
/// test DihedralBending.CylinderMatchesPlateEnergyWithStiffnessFromYoung). Other triangulations
/// and doubly curved bends differ by a factor of order one, which the wrinkle wavelength, going
/// as the fourth root of the bending stiffness, barely sees (docs/math/bending-from-material.md).
/// \pre E > 0, h > 0, -1 < nu < 1 (throws UsageError otherwise)
double dihedral_k_bending_from_young(double young, double poisson, double thickness);

/// Interface of a membrane energy density psi(Fbar).
class MembraneMaterial {
 public:
  virtual ~MembraneMaterial() = default;

  /// Short name used on the command line ("stvk", "corotated", ...).
  virtual std::string name() const = 0;

  /// Energy density per unit rest area.
  /// @param F  2x2 deformation gradient in the current edge-aligned frame (see file comment)
  virtual double psi(const Mat2& F, const ElementMaterialData& d) const = 0;

  /// First Piola-Kirchhoff stress dpsi/dF (2x2, same frame as F).
  virtual Mat2 pk1(const Mat2& F, const ElementMaterialData& d) const = 0;

  /// True when psi depends on the in-plane orientation of the frame (rotation-variant polar
  /// decomposition, linear strain), not only on C = F^T F. The element then skips a triangle
  /// whose current frame is undefined (math-spec 11, current area near zero).
  virtual bool frame_dependent() const = 0;
};

}  // namespace shellcontract
