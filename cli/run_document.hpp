// The input kept whole for `run`'s outputs (docs/design/attributes.md): read where a result uses
// it, dropped with a warning naming what is lost where it does not describe the simulated mesh.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "export_observer.hpp"
#include "shellcontract/mesh.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract::cli {

/// The input's document, so that an OBJ or PLY result keeps what the simulation does not use
/// (UVs, normals, groups, materials, polygons, extra properties) and --gltf its texture
/// coordinates, colours and materials. Held only where it is used (it is the whole file): an output
/// of the input's format, or a --gltf animation; otherwise null. A document that cannot be read, or
/// that is not the simulated mesh (`repaired`: --repair changed it), is a warning on stderr naming
/// what the result drops, and null. An output of another format than the input's is a warning
/// naming what it drops, where it drops something (`triangulated_polygons`: the input's polygons
/// of more than 3 corners, InputReport::triangulated_faces).
/// @throws InputError when the result is a .glb or .gltf (the input with new positions) and
///         there is no document to write it from, or when a glTF (that result or the --gltf
///         animation) cannot hold the document's texture coordinates or colours
///         (MeshDocument::require_gltf_values): found before the run
std::shared_ptr<const MeshDocument> run_input_document(const std::string& input,
                                                       const std::string& output,
                                                       bool gltf_animation, const Mesh& mesh,
                                                       bool repaired,
                                                       std::size_t triangulated_polygons);

/// What the --gltf animation takes from the input: its name, and from its document (null: none)
/// the texture coordinates, hard edges, colours and materials (the OBJ's .mtl, the PLY's
/// TextureFile images, the glTF's own); a problem with a material is a warning on stderr.
void prepare_gltf_animation(FrameExporter& exporter, const std::string& input,
                            const MeshDocument* document, const Mesh& mesh);

}  // namespace shellcontract::cli
