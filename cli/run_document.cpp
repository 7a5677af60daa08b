// run_input_document: the input kept whole for `run`'s outputs (run_document.hpp).
#include "run_document.hpp"

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <iostream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "command_line.hpp"
#include "export/gltf_material.hpp"
#include "mesh/file_extras.hpp"
#include "mesh/formats.hpp"
#include "mesh/read_polygon_soup.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/export.hpp"
#include "shellcontract/options.hpp"

namespace shellcontract::cli {
namespace {

/// Warns that the result is written by a plain writer, for `why`, naming what of the input it
/// drops as `repair` names it (repair.md, "What is written"): nothing is dropped without a word.
/// `triangulated`: the input's polygons of more than 3 corners, which the plain writers write as
/// their triangles. No warning when nothing is dropped (`always`: the warning without a list).
void warn_dropped(const std::string& input, const std::string& why, std::size_t triangulated,
                  bool always) {
  std::vector<std::string> dropped;
  try {
    dropped = describe_file_extras(lower_extension(input), read_file_bytes(input)).items;
  } catch (const InputError&) {
    // The file went away after it was read: the warning stays without the list.
  }
  if (triangulated > 0)
    dropped.push_back(std::to_string(triangulated) +
                      (triangulated == 1 ? " polygon" : " polygons") +
                      " with more than 3 corners (written as triangles)");
  if (dropped.empty() && !always) return;
  std::cerr << "warning: the result is written without the input's attributes: " << why;
  for (std::size_t i = 0; i < dropped.size(); ++i)
    std::cerr << (i ? "; " : " (dropped: ") << dropped[i];
  if (!dropped.empty()) std::cerr << ')';
  std::cerr << '\n';
}

bool is_gltf(const std::string& ext) { return is_mesh_format(ext, &MeshFormat::gltf); }

}  // namespace

std::shared_ptr<const MeshDocument> run_input_document(const std::string& input,
                                                       const std::string& output,
                                                       bool gltf_animation, const Mesh& mesh,
                                                       bool repaired,
                                                       std::size_t triangulated_polygons) {
  std::shared_ptr<const MeshDocument> document;
  const std::string in_ext = lower_extension(input), out_ext = lower_extension(output);
  // Another format than the input's is written by its plain writer (positions and triangles):
  // the result and its frames drop what the input has besides (a .glb or .gltf result of
  // another input is refused before, output_paths.cpp).
  if (in_ext != out_ext && !is_gltf(out_ext))
    warn_dropped(input, "it is a ." + out_ext + " file, the input a ." + in_ext + " file",
                 triangulated_polygons, false);
  if (in_ext != out_ext && !gltf_animation) return document;
  try {
    document = read_mesh_document(input);
  } catch (const InputError& e) {
    std::cerr << "warning: the result is written without the input's attributes: " << e.what()
              << '\n';
  }
  if (document && !document->matches(mesh)) {
    warn_dropped(input, repaired ? "--repair changed the mesh" : "the mesh is not the file's", 0,
                 true);
    document.reset();
  }
  // The library's rule, shared with the sweep's check of its meshes (check_run_input).
  require_run_document(input, document.get(), "see the warning above", out_ext, gltf_animation);
  return document;
}

void prepare_gltf_animation(FrameExporter& exporter, const std::string& input,
                            const MeshDocument* document, const Mesh& mesh) {
  // The positions a glTF holds as float32, relative to the mesh's centre (the node's
  // translation: write_gltf_animation), checked before the run as the colours are: found after
  // it, hours were spent on a file that cannot be written.
  {
    const Positions x = positions_from_mesh(mesh);
    const Vec3 centre = gltf_centre(x);
    for (Eigen::Index i = 0; i < x.rows(); ++i)
      for (int k = 0; k < 3; ++k)
        if (!(std::abs(x(i, k) - centre(k)) <=
              static_cast<double>(std::numeric_limits<float>::max())))
          throw InputError(input + ": --gltf cannot hold this mesh: a glTF stores positions as " +
                           "32-bit floats, relative to the mesh's centre, and vertex " +
                           std::to_string(i) + "'s " + "xyz"[k] + " is " +
                           shortest_text(x(i, k) - centre(k)) +
                           " from it, beyond the largest 32-bit float (3.40282347e+38); scale "
                           "the input down, or leave out --gltf");
  }
  exporter.set_gltf_name(std::filesystem::path(input).stem().string());
  if (!document) return;
  const CornerTexcoords uv = document->texcoords(mesh);
  exporter.set_texcoords(uv);
  exporter.set_normal_groups(document->normal_groups(mesh));  // the input's hard edges
  exporter.set_colours(document->colours(mesh));
  std::vector<std::string> material_warnings;
  GltfFaceMaterials m =
      gltf_materials(document->face_materials(mesh), !uv.empty(), material_warnings);
  exporter.set_materials(std::move(m.materials), std::move(m.face_material), std::move(m.source));
  for (const std::string& w : material_warnings) std::cerr << "warning: " << w << '\n';
}

}  // namespace shellcontract::cli
