// A closed mesh written as exporters write a mesh with one material per face range: one POSITION
// accessor, drawn by several primitives, each with its own indices accessor over a slice of the
// faces (and, where asked, its own NORMAL accessor), all of one node.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "support/gltf_files.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract::test {

/// The parts of `mesh` as primitives.size() primitives sharing POSITION accessor 0; primitive p
/// draws the p-th of that many consecutive face slices (the first ones one face longer where the
/// faces do not divide evenly). normal_of[p] >= 0: primitive p's NORMAL is accessor
/// 1 + normal_of[p], one per distinct value, each holding every vertex's unit position (the
/// sphere's normal); -1: no NORMAL. `materials`: primitive p has material p, named "m<p>".
inline GltfParts shared_position_parts(const TriMesh& mesh, const std::vector<int>& normal_of,
                                       bool materials = false) {
  std::string bin, views, accessors, prims;
  int next = 0;
  const auto add = [&](std::size_t offset, std::size_t count, int component, const char* type,
                       const std::string& minmax = "") {
    views += std::string(views.empty() ? "" : ",") +
             "{\"buffer\":0,\"byteOffset\":" + std::to_string(offset) +
             ",\"byteLength\":" + std::to_string(bin.size() - offset) + "}";
    accessors +=
        std::string(accessors.empty() ? "" : ",") + "{\"bufferView\":" + std::to_string(next) +
        ",\"componentType\":" + std::to_string(component) + ",\"count\":" + std::to_string(count) +
        ",\"type\":\"" + type + "\"" + minmax + "}";
    return next++;
  };
  const auto nv = static_cast<std::size_t>(mesh.x.rows());
  for (std::size_t v = 0; v < nv; ++v) {
    const float x[3] = {static_cast<float>(mesh.x(static_cast<Eigen::Index>(v), 0)),
                        static_cast<float>(mesh.x(static_cast<Eigen::Index>(v), 1)),
                        static_cast<float>(mesh.x(static_cast<Eigen::Index>(v), 2))};
    gltf_put(bin, x, 12);
  }
  // POSITION's bounds (the spec requires them): the sphere's, [-1, 1] on every axis.
  add(0, nv, 5126, "VEC3", ",\"min\":[-1,-1,-1],\"max\":[1,1,1]");
  int normals = 0;
  for (const int n : normal_of) normals = std::max(normals, n + 1);
  for (int n = 0; n < normals; ++n) {
    const std::size_t at = bin.size();
    for (std::size_t v = 0; v < nv; ++v) {
      const Vec3 u = mesh.x.row(static_cast<Eigen::Index>(v)).normalized();
      const float x[3] = {static_cast<float>(u[0]), static_cast<float>(u[1]),
                          static_cast<float>(u[2])};
      gltf_put(bin, x, 12);
    }
    add(at, nv, 5126, "VEC3");
  }
  std::string material_list;
  const std::size_t k = normal_of.size(), nf = static_cast<std::size_t>(mesh.faces.rows());
  for (std::size_t p = 0, face = 0; p < k; ++p) {
    const std::size_t count = nf / k + (p < nf % k ? 1 : 0), at = bin.size();
    for (std::size_t f = face; f < face + count; ++f)
      for (int c = 0; c < 3; ++c) {
        const auto i = static_cast<std::uint32_t>(mesh.faces(static_cast<Eigen::Index>(f), c));
        gltf_put(bin, &i, 4);
      }
    face += count;
    const int idx = add(at, 3 * count, 5125, "SCALAR");
    prims += std::string(prims.empty() ? "" : ",") + "{\"attributes\":{\"POSITION\":0" +
             (normal_of[p] >= 0 ? ",\"NORMAL\":" + std::to_string(1 + normal_of[p]) : "") +
             "},\"indices\":" + std::to_string(idx) +
             (materials ? ",\"material\":" + std::to_string(p) : "") + "}";
    material_list +=
        std::string(material_list.empty() ? "" : ",") + "{\"name\":\"m" + std::to_string(p) + "\"}";
  }
  GltfParts out;
  out.bin = bin;
  out.json =
      "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{"
      "\"mesh\":0}],\"meshes\":[{\"primitives\":[" +
      prims + "]}],\"accessors\":[" + accessors + "],\"bufferViews\":[" + views +
      "],\"buffers\":[{\"byteLength\":" + std::to_string(bin.size()) + "%URI%}]" +
      (materials ? ",\"materials\":[" + material_list + "]" : "") + "}";
  return out;
}

}  // namespace shellcontract::test
