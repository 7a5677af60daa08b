// A result stored as 32-bit floats (a PLY's float x, y, z, a glTF's POSITION): how coarse the
// rounding is beside the contact gap the run kept, and the positions as such a file holds them
// (docs/design/attributes.md, "Float32 positions").
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "shellcontract/mesh_io.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// The distance from the 32-bit float nearest |v| to the next larger one: how far apart the
/// values that a float32 coordinate of that size can take are.
double float32_spacing(double v);

/// Whether positions stored with `spacing` (in the units of `gap`) can undo the contact gap the
/// run kept: spacing above a quarter of `gap` (float32_positions.cpp says why). A gap of 0
/// (collisions off: nothing was kept apart) is never undone.
bool float32_too_coarse(double spacing, double gap);

/// The float32 spacing at the largest coordinate of x as `doc` stores them, in x's units (a
/// glTF's node space mapped back by the node's transform); 0 where the document stores them
/// exactly (an OBJ's text, a PLY's double or integer x, y, z).
/// @param x the document's vertices' positions (input_positions), input units
double stored_float32_spacing(const MeshDocument& doc, const Positions& x);

/// doc.text_for(output_path, x, warnings), but a PLY whose float32 x, y, z are too coarse for
/// `gap` (float32_too_coarse) gets them as double, its header's types too, with a warning naming
/// the spacing and the gap appended to `warnings` (which may be null).
std::string text_keeping_gap(const MeshDocument& doc, const std::string& output_path,
                             const Positions& x, double gap, std::vector<std::string>* warnings);

/// x as the file that text_keeping_gap(doc, ..., x, gap, ...) writes holds them, read back
/// (rounded to float32 where it stores them so); nullopt where it stores them exactly.
std::optional<Positions> stored_positions(const MeshDocument& doc, const Positions& x, double gap);

/// What the PLY and glTF documents answer for the functions above (nullopt: `doc` is not theirs).
std::optional<double> ply_float32_spacing(const MeshDocument& doc, const Positions& x);
std::optional<std::string> ply_text_for(const MeshDocument& doc, const std::string& output_path,
                                        const Positions& x, bool widen,
                                        std::vector<std::string>* warnings);
/// x with the PLY's float32 x, y, z rounded to float32 (nullopt: not a PLY document).
std::optional<Positions> ply_rounded(const MeshDocument& doc, const Positions& x);
std::optional<double> gltf_float32_spacing(const MeshDocument& doc, const Positions& x);
/// x through the node space, rounded there to float32 and back (nullopt: not a glTF document).
std::optional<Positions> gltf_rounded(const MeshDocument& doc, const Positions& x);

}  // namespace shellcontract
