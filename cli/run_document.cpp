// run_input_document: the input kept whole for `run`'s outputs (run_document.hpp).
#include "run_document.hpp"

#include <cstddef>
#include <iostream>

#include "command_line.hpp"
#include "mesh/file_extras.hpp"
#include "mesh/read_polygon_soup.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract::cli {

std::shared_ptr<const MeshDocument> run_input_document(const std::string& input,
                                                       const std::string& output,
                                                       bool gltf_animation, const Mesh& mesh,
                                                       bool repaired) {
  std::shared_ptr<const MeshDocument> document;
  if (lower_extension(input) != lower_extension(output) && !gltf_animation) return document;
  try {
    document = read_mesh_document(input);
  } catch (const InputError& e) {
    std::cerr << "warning: the result is written without the input's attributes: " << e.what()
              << '\n';
  }
  if (document && !document->matches(mesh)) {
    std::cerr << "warning: the result is written without the input's attributes: "
              << (repaired ? "--repair changed the mesh" : "the mesh is not the file's");
    // Which ones, named as `repair` names them: nothing is dropped without a word.
    try {
      const FileExtras extras =
          describe_file_extras(lower_extension(input), read_file_bytes(input));
      for (std::size_t i = 0; i < extras.items.size(); ++i)
        std::cerr << (i ? "; " : " (dropped: ") << extras.items[i];
      if (!extras.items.empty()) std::cerr << ')';
    } catch (const InputError&) {
      // The file went away after it was read: the warning stays without the list.
    }
    std::cerr << '\n';
    document.reset();
  }
  // Checked before the run: a result that cannot be written is not worth computing.
  if (!document && (lower_extension(output) == "glb" || lower_extension(output) == "gltf"))
    throw InputError(input + ": the ." + lower_extension(output) +
                     " result would be this file with new positions, and it cannot be written "
                     "so (see the warning above); "
                     "choose an .obj, .ply, .off or .stl output");
  // What a glTF holds as float32 (texture coordinates, colours), checked before the run too:
  // found after it, the animation failed with no file or element named (exit 2 here instead).
  if (document &&
      (gltf_animation || lower_extension(output) == "glb" || lower_extension(output) == "gltf"))
    document->require_gltf_values();
  return document;
}

}  // namespace shellcontract::cli
