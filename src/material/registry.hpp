// Name <-> model registry of the membrane materials and anisotropic fibre energies (used by cli/
// and sim/), and the dispatch templates the PBD solver uses to instantiate its loop on the
// concrete model type (material.hpp: the per-element calls are then devirtualized).
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "material/active_fiber.hpp"
#include "material/anisotropic_arap.hpp"
#include "material/anisotropic_sqrt.hpp"
#include "material/anisotropic_stvk.hpp"
#include "material/corotated.hpp"
#include "material/linear.hpp"
#include "material/mooney_rivlin.hpp"
#include "material/stvk.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/material.hpp"
#include "shellcontract/simulation_options.hpp"

namespace shellcontract {

/// The "energy" of AnisoKind::None: psi = 0, P = 0 for every F. It exists so that with_aniso()
/// can call its functor for every AnisoKind with a type that has the material interface; a loop
/// instantiated on it does nothing (and a solver should not build E_A constraints at all).
class NoAniso final : public MembraneMaterial {
 public:
  NoAniso() = default;
  explicit NoAniso(const MaterialParams&) {}
  std::string name() const override { return "none"; }
  bool frame_dependent() const override { return false; }
  double psi(const Mat2&, const ElementMaterialData&) const override { return 0.0; }
  Mat2 pk1(const Mat2&, const ElementMaterialData&) const override { return Mat2::Zero(); }
};

/// Parses a membrane material name (exact, lower case, see MaterialKind).
/// \throws UsageError naming the valid names when `name` is not one of them
MaterialKind parse_material_kind(const std::string& name);

/// Parses an anisotropic energy name (exact, lower case, see AnisoKind).
/// \throws UsageError naming the valid names when `name` is not one of them
AnisoKind parse_aniso_kind(const std::string& name);

/// Every valid material name, in MaterialKind order.
std::vector<std::string> material_names();

/// Every valid anisotropic energy name, in AnisoKind order ("none" first).
std::vector<std::string> aniso_names();

/// The name of a material kind; parse_material_kind(to_string(k)) == k.
std::string to_string(MaterialKind kind);

/// The name of an anisotropic kind; parse_aniso_kind(to_string(k)) == k.
std::string to_string(AnisoKind kind);

/// Heap-allocated model for virtual use (tests, tools). Parameters as in each model's header.
/// \throws UsageError for an out-of-range enum value
std::unique_ptr<MembraneMaterial> make_material(MaterialKind kind, const MaterialParams& params);

/// Heap-allocated anisotropic model, nullptr for AnisoKind::None.
/// \throws UsageError for an out-of-range enum value or invalid parameters (ActiveFiber: gamma)
std::unique_ptr<MembraneMaterial> make_aniso(AnisoKind kind, const MaterialParams& params);

/// Constructs the concrete model of `kind` and returns fn(const Concrete&), e.g.
///   with_material(kind, params, [&](const auto& m) { run_loop(m); });
/// fn must return the same type for every model, and must not return a reference to its
/// argument (the model is a local of this function).
/// \throws UsageError for an out-of-range enum value
template <class Fn>
decltype(auto) with_material(MaterialKind kind, const MaterialParams& params, Fn&& fn) {
  switch (kind) {
    case MaterialKind::Stvk: {
      const Stvk m(params);
      return std::forward<Fn>(fn)(m);
    }
    case MaterialKind::Corotated: {
      const Corotated m(params);
      return std::forward<Fn>(fn)(m);
    }
    case MaterialKind::Linear: {
      const Linear m(params);
      return std::forward<Fn>(fn)(m);
    }
    case MaterialKind::MooneyRivlin: {
      const MooneyRivlin m(params);
      return std::forward<Fn>(fn)(m);
    }
  }
  throw UsageError("with_material: invalid MaterialKind " + std::to_string(static_cast<int>(kind)));
}

/// As with_material() for the anisotropic energies. AnisoKind::None calls fn(const NoAniso&)
/// (psi = P = 0), so every kind dispatches; callers that can skip E_A entirely should check for
/// None first.
/// \throws UsageError for an out-of-range enum value or invalid parameters (ActiveFiber: gamma)
template <class Fn>
decltype(auto) with_aniso(AnisoKind kind, const MaterialParams& params, Fn&& fn) {
  switch (kind) {
    case AnisoKind::None: {
      const NoAniso m(params);
      return std::forward<Fn>(fn)(m);
    }
    case AnisoKind::Arap: {
      const AnisotropicArap m(params);
      return std::forward<Fn>(fn)(m);
    }
    case AnisoKind::Stvk: {
      const AnisotropicStvk m(params);
      return std::forward<Fn>(fn)(m);
    }
    case AnisoKind::Sqrt: {
      const AnisotropicSqrt m(params);
      return std::forward<Fn>(fn)(m);
    }
    case AnisoKind::ActiveFiber: {
      const ActiveFiber m(params);
      return std::forward<Fn>(fn)(m);
    }
  }
  throw UsageError("with_aniso: invalid AnisoKind " + std::to_string(static_cast<int>(kind)));
}

}  // namespace shellcontract
