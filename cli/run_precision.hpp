// A `run` result that its output stores as 32-bit floats, a glTF's or a float PLY's
// (mesh/float32_positions.hpp): the warning before a glTF run whose float32 positions are too
// coarse for the contact gap, and `validate`'s judgement of the positions as the file holds them.
#pragma once

#include <string>

#include "shellcontract/mesh.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"
#include "stage_notice.hpp"

namespace shellcontract::cli {

/// The gap the run keeps between surfaces in contact, in input units: the collision response
/// pushes a pair closer than the contact distance `delta` (normalized units, RunResult::
/// contact_distance) to RESPONSE_FACTOR delta, and a normalized unit is the input's bounding
/// diagonal `scale` (RunResult::normalization_scale). 0 with collisions off (delta 0).
double contact_gap(double delta, double scale);

/// Before the run: a warning on `notice` when `output` is a glTF (the input with new positions,
/// stored as float32 in its nodes' space) and the float32 spacing at the input's largest
/// coordinate is too coarse for the contact gap the run will keep (float32_too_coarse): the
/// written result could pass through itself. The gap is estimated from `options` (--delta auto:
/// the mean edge's share, which the run may lower further).
std::string warn_float32_gltf(const std::string& output, const MeshDocument* document,
                              const Mesh& mesh, const RunOptions& options, StageNotice& notice);

/// After the run, with `validate`: when the -o file (`output`, written from `document`) stores
/// the positions as float32 (a glTF, a float PLY not widened: text_keeping_gap), the result is
/// checked for new self-intersections as the file holds them, and r.new_intersections is the
/// larger count; a new pair there makes a completed (or target-not-reached) run
/// RunStatus::NewIntersections, its message saying the rounding caused it. Skipped for a run
/// never validated (new_intersections -1) or cancelled; out of memory while checking leaves `r`
/// as it was, with a warning.
void validate_as_written(const std::string& output, const MeshDocument* document, const Mesh& mesh,
                         const RunOptions& options, RunResult& r, StageNotice& notice);

}  // namespace shellcontract::cli
