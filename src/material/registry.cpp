// Name <-> model registry (material/registry.hpp).
#include "material/registry.hpp"

#include <array>
#include <type_traits>
#include <utility>

namespace shellcontract {
namespace {

// One table per enum, in enum order; every name lookup goes through it.
const std::array<std::pair<MaterialKind, const char*>, 4> MATERIAL_TABLE{{
    {MaterialKind::Stvk, "stvk"},
    {MaterialKind::Corotated, "corotated"},
    {MaterialKind::Linear, "linear"},
    {MaterialKind::MooneyRivlin, "mooney-rivlin"},
}};

const std::array<std::pair<AnisoKind, const char*>, 5> ANISO_TABLE{{
    {AnisoKind::None, "none"},
    {AnisoKind::Arap, "arap"},
    {AnisoKind::Stvk, "stvk"},
    {AnisoKind::Sqrt, "sqrt"},
    {AnisoKind::ActiveFiber, "active-fiber"},
}};

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

}  // namespace

MaterialKind parse_material_kind(const std::string& name) {
  for (const auto& [kind, n] : MATERIAL_TABLE)
    if (name == n) return kind;
  throw UsageError("unknown material '" + name + "' (valid: " + join(material_names()) + ")");
}

AnisoKind parse_aniso_kind(const std::string& name) {
  for (const auto& [kind, n] : ANISO_TABLE)
    if (name == n) return kind;
  throw UsageError("unknown anisotropic energy '" + name + "' (valid: " + join(aniso_names()) +
                   ")");
}

std::vector<std::string> material_names() {
  std::vector<std::string> out;
  for (const auto& entry : MATERIAL_TABLE) out.emplace_back(entry.second);
  return out;
}

std::vector<std::string> aniso_names() {
  std::vector<std::string> out;
  for (const auto& entry : ANISO_TABLE) out.emplace_back(entry.second);
  return out;
}

std::string to_string(MaterialKind kind) {
  for (const auto& [k, n] : MATERIAL_TABLE)
    if (k == kind) return n;
  throw UsageError("to_string: invalid MaterialKind " + std::to_string(static_cast<int>(kind)));
}

std::string to_string(AnisoKind kind) {
  for (const auto& [k, n] : ANISO_TABLE)
    if (k == kind) return n;
  throw UsageError("to_string: invalid AnisoKind " + std::to_string(static_cast<int>(kind)));
}

std::unique_ptr<MembraneMaterial> make_material(MaterialKind kind, const MaterialParams& params) {
  return with_material(kind, params, [](const auto& m) -> std::unique_ptr<MembraneMaterial> {
    return std::make_unique<std::decay_t<decltype(m)>>(m);
  });
}

std::unique_ptr<MembraneMaterial> make_aniso(AnisoKind kind, const MaterialParams& params) {
  if (kind == AnisoKind::None) return nullptr;
  return with_aniso(kind, params, [](const auto& m) -> std::unique_ptr<MembraneMaterial> {
    return std::make_unique<std::decay_t<decltype(m)>>(m);
  });
}

}  // namespace shellcontract
