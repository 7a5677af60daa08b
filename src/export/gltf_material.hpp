// The glTF materials of an OBJ input (docs/design/export.md, "Name and material"): the .mtl files
// its mtllib lines name, read for the keys a base colour needs (newmtl, Kd, d, Tr, map_Kd), and the
// materials its faces use, with their diffuse textures' files embedded; and those of a PLY input,
// one per texture file its header names (`comment TextureFile`), with that image embedded.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "shellcontract/export.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {

/// One `newmtl` of a .mtl file, as far as a glTF base colour goes.
struct MtlMaterial {
  std::string name;
  std::array<double, 3> kd{1.0, 1.0, 1.0};  ///< Kd; white when absent (map_Kd alone shows as is)
  double alpha = 1.0;                        ///< d, or 1 - Tr; d wins when both are given
  std::string texture;       ///< map_Kd's file, relative paths from the .mtl's folder; empty none
  std::size_t texture_line = 0;  ///< the map_Kd line (1-based)
  std::string file;              ///< the .mtl file, for messages
};

/// The materials of a .mtl file's bytes. Other keys are skipped. A line that cannot be read (a
/// Kd without three numbers, a d outside [0, 1], a key before any newmtl, a newmtl without a
/// name) is a warning "<name>: line <n>: ..." appended to `warnings`, and the key is left at its
/// default (a nameless material is kept: the lines after it are its own, though none can use it).
/// @param name the file, for messages; relative map_Kd paths start from its folder
std::vector<MtlMaterial> parse_mtl(const std::string& name, const std::string& bytes,
                                   std::vector<std::string>& warnings);

/// An image file that a .mtl file names.
struct MtlTextureFile {
  std::string path;  ///< as parse_mtl resolves map_Kd's: relative paths from the .mtl's folder
  std::string key;   ///< the key that names it ("map_Kd", "bump")
  std::size_t line = 0;
};

/// Every image file that the .mtl file `path` names, under any texture key: map_Kd, which the
/// glTF uses, and those a renderer of the OBJ reads besides (every map_* but map_aat, bump,
/// disp, decal, refl, norm), so that no output replaces one (output_check.cpp). File names are
/// read as map_Kd's (options skipped). Empty when the file cannot be read (read with
/// gltf_materials' bounds); never throws for its contents.
std::vector<MtlTextureFile> mtl_texture_files(const std::string& path);

/// The glTF materials of an OBJ's faces and which face has which.
struct GltfFaceMaterials {
  std::vector<GltfMaterial> materials;  ///< the defined materials the faces use, in order of first use
  std::vector<int> face_material;       ///< per face: index into materials; -1 none (empty: no face has one)
  std::shared_ptr<const tinygltf::Model> source;  ///< GltfAnimation::material_source
};

/// The materials of the mesh's faces for the glTF (GltfAnimation::materials and face_material):
/// each material a face uses and a library defines (the first definition in the order of the
/// mtllib lines). A face of a material that no library defines has none, with one warning per
/// such material. A texture (map_Kd) is embedded when the file exists and is a PNG or JPEG (by
/// its first bytes) and `has_texcoords`; otherwise the material is written without it, with a
/// warning naming the .mtl file and line. A library that is missing or unreadable is a warning
/// too. Never throws for the files' contents.
/// Each file is read once (by file_key: any spelling of it): a library that several mtllib
/// names give is read at its first one, and the materials whose textures are one file share its
/// bytes (GltfMaterial::image), each with its own warnings.
/// For a PLY's texture files (materials.textures not empty: no library is read), one white
/// material per texture file a face uses, in header order, named by the path as the header
/// writes it, its image embedded under the same conditions, the warnings naming the PLY and the
/// TextureFile comment's header line; a face whose texnumber names no texture file has no
/// material (one warning for them all).
/// For a glTF's materials (materials.gltf set), gltf_input_materials (gltf_input_materials.hpp).
GltfFaceMaterials gltf_materials(const FaceMaterials& materials, bool has_texcoords,
                                 std::vector<std::string>& warnings);

/// "image/png" or "image/jpeg" by the file's signature; empty for anything else.
std::string image_mime_type(const std::vector<unsigned char>& bytes);

}  // namespace shellcontract
