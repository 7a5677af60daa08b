// The mesh formats, one row each (private to the tree; docs/architecture.md, "A new input
// format"). A file's format is its extension alone, and every list of formats in the code is
// made from this table: the readers' and writers' checks, their messages and the help texts.
// A reader or writer that picks its code by format switches on FormatId without a default, so
// that a new row is a -Wswitch warning in each place that must handle it.
// tests/mesh/test_formats.cpp reads and writes every row and compares each message's list with
// the table's.
#pragma once

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace shellcontract {

enum class FormatId { Off, Obj, Ply, Stl, Glb, Gltf };

/// One format. Every row is read by read_input_mesh (read_polygon_soup, file_extras.hpp's
/// describe_file_extras) and written by `repair` (a plain writer's or, for glTF, the glTF mesh
/// writer's file).
struct MeshFormat {
  FormatId id;
  const char* ext;  ///< lower case, without the dot
  /// Written from positions and faces alone by write_mesh_atomic, write_polygon_soup_atomic and
  /// the frame sequence: `run`'s result of any input and its frames.
  bool plain_writer;
  /// Kept whole by read_mesh_document (texture coordinates, materials, colours, a glTF's scene):
  /// a result in the input's format is the input with new positions.
  bool document;
  /// A glTF: written only from a document (`run`) or by the glTF mesh writer (`repair`).
  bool gltf;
  /// May name other files (materials, textures, buffers) that an output must not replace
  /// (input_dependencies).
  bool names_files;
  /// The plain writer writes it binary on request.
  bool binary_writer;
  /// Numbers its vertices: not STL, whose facets hold their corners' positions (size estimates;
  /// two vertices at one position become one when read back).
  bool indexed_vertices;
  /// Holds every vertex as the doubles given: not STL (vertices at one position merge, binary
  /// STL holds floats), not glTF (32-bit floats). The formats messages suggest when a position
  /// would not survive the others.
  bool exact_positions;
};

// clang-format off
inline constexpr MeshFormat MESH_FORMATS[] = {
    // id             ext     plain  doc    gltf   files  binary indexed exact
    {FormatId::Off,  "off",  true,  false, false, false, false, true,   true},
    {FormatId::Obj,  "obj",  true,  true,  false, true,  false, true,   true},
    {FormatId::Ply,  "ply",  true,  true,  false, true,  true,  true,   true},
    {FormatId::Stl,  "stl",  true,  false, false, false, true,  false,  false},
    {FormatId::Glb,  "glb",  false, true,  true,  true,  false, true,   false},
    {FormatId::Gltf, "gltf", false, true,  true,  true,  false, true,   false},
};
// clang-format on

/// A path's extension in lower case without its dot ("OBJ" -> "obj"; "" when it has none): the
/// name by which the readers and writers pick a format.
inline std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

/// The row of a lower-case extension (lower_extension's); nullptr for none.
inline const MeshFormat* find_mesh_format(std::string_view ext) {
  for (const MeshFormat& f : MESH_FORMATS)
    if (ext == f.ext) return &f;
  return nullptr;
}

/// The row of a path, by its extension; nullptr for none.
inline const MeshFormat* mesh_format_of(const std::string& path) {
  return find_mesh_format(lower_extension(path));
}

/// Whether `ext` (lower case) is a format of the table that `keep` selects.
template <class Keep>
bool is_mesh_format(std::string_view ext, Keep keep) {
  const MeshFormat* f = find_mesh_format(ext);
  return f && std::invoke(keep, *f);
}

/// Every row (for extension_list, is_mesh_format).
inline bool any_format(const MeshFormat&) { return true; }

/// The rows that `keep` selects (a predicate or a bool member), in the table's order, as
/// `dot` + ext joined by ", " and the last by `last`: (&MeshFormat::plain_writer, ".", " or ")
/// is ".off, .obj, .ply or .stl"; (any_format, "", ", ") "off, obj, ply, stl, glb, gltf".
template <class Keep>
std::string extension_list(Keep keep, std::string_view dot = ".", std::string_view last = " or ") {
  std::string out;
  std::size_t n = 0, count = 0;
  for (const MeshFormat& f : MESH_FORMATS) count += std::invoke(keep, f) ? 1 : 0;
  for (const MeshFormat& f : MESH_FORMATS) {
    if (!std::invoke(keep, f)) continue;
    if (n > 0) out += n + 1 == count ? last : std::string_view(", ");
    out.append(dot).append(f.ext);
    ++n;
  }
  return out;
}

}  // namespace shellcontract
