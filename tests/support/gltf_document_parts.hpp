// A glTF document with the elements that tinygltf's writer alone does not round-trip
// (src/mesh/gltf_json.hpp), for the document tests (tests/export/test_gltf_document_json.cpp)
// and the glTF validator's sample runs (tests/tools/write_gltf_document.cpp).
#pragma once

#include <stdexcept>
#include <string>

#include "support/gltf_files.hpp"
#include "support/textured_octahedron.hpp"

namespace shellcontract::test {

/// Replaces the first `from` in `s` by `to`.
/// @throws std::logic_error when `s` has no `from` (the fixture's JSON changed)
inline void replace_once(std::string& s, const std::string& from, const std::string& to) {
  const std::size_t at = s.find(from);
  if (at == std::string::npos) throw std::logic_error("replace_once: no " + from);
  s.replace(at, from.size(), to);
}

/// The textured octahedron drawn by node 0 of scene 1, with empty scenes (0, and 2 but for empty
/// extras), an empty
/// node (1), a node with an infinite perspective camera (2), an orthographic camera, a sampler
/// without wrap modes or filters, KHR_materials_unlit (always {}), and empty extras.
inline GltfParts document_parts() {
  GltfScene s;
  s.primitives.push_back(octahedron_primitive(true, true));
  s.node_transform = "\"translation\":[3,-1,2],\"name\":\"shell\"";
  const auto& png = tiny_png();
  s.png.assign(png.begin(), png.end());
  s.extra =
      "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":1,\"znear\":0.1}},"
      "{\"type\":\"orthographic\",\"orthographic\":{\"xmag\":1,\"ymag\":2,\"znear\":0.1,"
      "\"zfar\":50}}],\"samplers\":[{}],\"extensionsUsed\":[\"KHR_materials_unlit\"],"
      "\"extras\":{\"empty\":{},\"list\":[],\"note\":\"kept\"}";
  GltfParts parts = gltf_parts(s);
  replace_once(parts.json, "\"scene\":0,\"scenes\":[{\"nodes\":[0]}]",
               "\"scene\":1,\"scenes\":[{},{\"nodes\":[0,2],\"name\":\"main\"},{\"extras\":{}}]");
  replace_once(parts.json, "\"name\":\"shell\"}]",
               "\"name\":\"shell\",\"extras\":{}},{},{\"camera\":0,\"translation\":[0,0,9]}]");
  replace_once(parts.json, "\"materials\":[{\"name\":\"skin\",",
               "\"materials\":[{\"name\":\"skin\",\"extensions\":{\"KHR_materials_unlit\":{}},"
               "\"extras\":{},");
  replace_once(parts.json, "\"textures\":[{\"source\":0}]",
               "\"textures\":[{\"source\":0,\"sampler\":0}]");
  replace_once(parts.json, "\"meshes\":[{", "\"meshes\":[{\"extras\":{\"tags\":[]},");
  return parts;
}

}  // namespace shellcontract::test
