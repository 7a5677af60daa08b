// The material's settings as plain data: which membrane and fibre energies, and their
// parameters. A leaf: the run options (sim/config.hpp) include this, not the material classes
// (material.hpp, registry.hpp).
#pragma once

namespace shellcontract {

/// Isotropic membrane energy E_S (math-spec 6). Names: "stvk", "corotated", "linear",
/// "mooney-rivlin".
enum class MaterialKind { Stvk, Corotated, Linear, MooneyRivlin };

/// Anisotropic fibre energy E_A (math-spec 7). Names: "none", "arap", "stvk", "sqrt",
/// "active-fiber". Each model's name() equals its name here.
enum class AnisoKind { None, Arap, Stvk, Sqrt, ActiveFiber };

/// Membrane stiffness parameters. Units: energy per unit rest area (N/m for a membrane in SI).
struct MaterialParams {
  double mu = 1.0;           ///< shear modulus (Lame mu), default 1 (math-spec 14)
  double lambda = 1.0;       ///< plane-stress Lame lambda, default lambda/mu = 1 (math-spec 14)
  double c10 = 0.5;          ///< Mooney-Rivlin C10, default mu/2 (math-spec 14)
  double c01 = 0.0;          ///< Mooney-Rivlin C01, default 0 (neo-Hookean membrane)
  double mu_aniso = 1.0;     ///< anisotropic fibre stiffness mu_A
  double fiber_target = 1.0; ///< active-fibre target stretch gamma in (0, 1] (math-spec 7)
};

}  // namespace shellcontract
