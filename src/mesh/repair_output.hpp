// What `repair` writes (private to src/mesh; cli/repair.cpp): the input unchanged when it was
// usable, and otherwise the repaired mesh, keeping what can be kept and naming what cannot.
#pragma once

#include <string>
#include <vector>

#include "shellcontract/repair.hpp"

namespace shellcontract {

/// How write_repair_output wrote the output.
struct RepairOutput {
  enum class Kind {
    Copy,       ///< the input was usable and the output has its format: the input's bytes
    Converted,  ///< the input was usable, the output has another format: its vertices and polygons
    Repaired,   ///< repair changed the mesh: the repaired mesh
  };
  Kind kind = Kind::Copy;
  bool binary = false;  ///< the output is a binary PLY or STL, or a .glb
  /// What of the input the output does not carry, one phrase each ("154 texture coordinates
  /// (vt)", "72 polygons with more than 3 corners (triangulated)"); empty for a copy.
  std::vector<std::string> dropped;
  /// A copy of an OBJ into another folder: its mtllib paths were rewritten to name the same
  /// .mtl files from there (obj_material_paths.hpp); the other bytes are the input's.
  bool material_paths_rewritten = false;
  /// "<input>: line <n>: ..." for a material library that does not exist (kept as written);
  /// "<output>: names '<uri>' ..." for a buffer or image file of a .gltf copied into another
  /// folder that is beside the input but not beside the copy.
  std::vector<std::string> warnings;
  /// "copy", "converted" or "repaired".
  std::string kind_name() const;
};

/// Refuses an output name whose extension (in any case) is none of the formats `repair` writes
/// (formats.hpp: a plain writer's or a glTF; today every format read). The CLI asks before the
/// repair, so that a name it cannot write is bad usage whatever the input, as `run` checks -o
/// before reading; and write_repair_output asks again first.
/// @throws UsageError naming `option` (the CLI's "-o"), the output and every format written
void check_repair_output_name(const std::string& option, const std::string& output);

/// Writes `repair`'s output: `mesh` and `report` are what repair_input_mesh returned for `input`.
/// - A usable input (report.already_usable) to the same format (extension, in any case): the
///   input's bytes, unchanged (UVs, groups, materials, polygons, comments, a binary encoding...),
///   but for an OBJ's mtllib paths when the output is in another folder: they are rewritten to
///   name the same .mtl files from there (material_paths_rewritten, warnings).
/// - A usable input to another format: the file's own vertices and polygons as read (their order,
///   corners and winding, also of an inside-out input); an STL gets the triangles read_input_mesh
///   makes of the polygons, in the polygons' winding. What the format cannot hold is dropped.
/// - A repaired input: the repaired mesh (repair rebuilds vertices and faces, so the file's
///   per-corner, per-face and per-vertex data are dropped).
/// A binary input gives a binary output where the positions fit: a PLY (doubles), or an STL from
/// an STL (floats); otherwise text, and "the binary encoding" is among the dropped.
/// A .glb or .gltf that is not a copy is a bare glTF of the triangles (gltf_mesh_writer.hpp):
/// positions rounded to floats (named among the dropped when that changes one), checked as
/// `check` would before it is written.
/// Written atomically (write_file_atomic): a failure leaves no file.
/// @throws InputError naming the input if it cannot be read again
/// @throws UsageError if the output's name is none of the formats (check_repair_output_name), if
///         it cannot be written, or is an STL in which two vertices would
///         be stored at the same position (an STL reader merges them: another mesh), or a glTF
///         whose positions, rounded to floats, make a mesh that the usability check refuses
RepairOutput write_repair_output(const std::string& input, const std::string& output, const Mesh& mesh,
                                 const RepairReport& report);

}  // namespace shellcontract
