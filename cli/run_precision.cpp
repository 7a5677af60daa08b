// A `run` result stored as 32-bit floats (run_precision.hpp).
#include "run_precision.hpp"

#include <algorithm>
#include <new>
#include <optional>

#include "collision/self_collision/common.hpp"
#include "mesh/float32_positions.hpp"
#include "mesh/formats.hpp"
#include "mesh/normalization.hpp"
#include "shellcontract/validation.hpp"
#include "sim/contact_distance.hpp"

namespace shellcontract::cli {

double contact_gap(double delta, double scale) {
  return collision_pipeline::RESPONSE_FACTOR * delta * scale;
}

std::string warn_float32_gltf(const std::string& output, const MeshDocument* document,
                              const Mesh& mesh, const RunOptions& options, StageNotice& notice) {
  if (!document || !options.sim.collisions ||
      !is_mesh_format(lower_extension(output), &MeshFormat::gltf))
    return {};
  const Positions x = positions_from_mesh(mesh);
  const double scale = compute_normalization(x).scale;
  double delta = options.sim.collision.delta;
  if (options.sim.auto_delta)
    delta = std::min(delta, AUTO_DELTA_PER_MEAN_EDGE * mean_edge_length(mesh) / scale);
  const double gap = contact_gap(delta, scale);
  const double spacing = stored_float32_spacing(*document, input_positions(mesh, x));
  if (!float32_too_coarse(spacing, gap)) return {};
  const std::string w =
      "the ." + lower_extension(output) +
      " result stores its positions as 32-bit floats, whose spacing at the input's "
      "largest coordinate, " +
      shortest_text(spacing) + ", is more than a quarter of the contact gap " + shortest_text(gap) +
      " that the run keeps between the surfaces (2 delta times the mesh's diagonal): "
      "rounded so, the written result can pass through itself where surfaces touch; "
      "move the mesh near the origin (into its node's translation), or write an "
      "OBJ, OFF or PLY result";
  notice.line("warning: " + w);
  return w;
}

void validate_as_written(const std::string& output, const MeshDocument* document, const Mesh& mesh,
                         const RunOptions& options, RunResult& r, StageNotice& notice) {
  if (options.sim.validate == ValidateMode::Off || r.new_intersections < 0 ||
      r.status == RunStatus::Cancelled || !document ||
      document->format() != lower_extension(output) || !r.positions.allFinite())
    return;
  const double gap = contact_gap(r.contact_distance, r.normalization_scale);
  const std::optional<Positions> stored =
      stored_positions(*document, input_positions(mesh, r.positions), gap);
  if (!stored) return;
  notice.begin("checking the result as " + output + " stores it for self-intersections");
  long found = -1;
  try {
    // The file's vertices back to the mesh's (a welded vertex: its first copy in the file).
    Positions x = r.positions;
    const std::vector<std::size_t> map = input_vertex_map(mesh);
    std::vector<bool> seen(static_cast<std::size_t>(x.rows()), false);
    for (std::size_t i = 0; i < map.size(); ++i)
      if (!seen[map[i]]) {
        seen[map[i]] = true;
        x.row(static_cast<Eigen::Index>(map[i])) = stored->row(static_cast<Eigen::Index>(i));
      }
    // The run validated this input, so its own pairs are within the baseline's bound.
    const std::size_t limit = baseline_pair_limit(mesh.number_of_faces());
    const SelfIntersectionCount own =
        count_self_intersections(mesh, positions_from_mesh(mesh), limit, limit);
    if (own.complete) found = static_cast<long>(new_self_intersections(mesh, x, own.first));
  } catch (const std::bad_alloc&) {
    notice.end();
    notice.line("warning: out of memory while checking the result as " + output +
                " stores it (32-bit floats); only the computed positions were checked");
    return;
  }
  notice.end();
  const long computed = r.new_intersections;
  if (found <= computed) return;
  r.new_intersections = found;
  if (r.status == RunStatus::NewIntersections) {
    // The run's own check found pairs already: its message gives the file's count as well.
    r.message +=
        "; " + std::to_string(found) + " as " + output + " stores the result (its 32-bit floats)";
  } else if (r.status == RunStatus::Completed || r.status == RunStatus::TargetNotReached) {
    // As the run's own check: new pairs come before a target not reached, whose words stay.
    const std::string before = r.status == RunStatus::TargetNotReached ? "; " + r.message : "";
    r.status = RunStatus::NewIntersections;
    r.message = std::to_string(found) + " new self-intersecting face pairs at the end as " +
                output + " stores the result (its 32-bit floats; the computed positions have " +
                std::to_string(computed) + ")" + before;
  }
}

}  // namespace shellcontract::cli
