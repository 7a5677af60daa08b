// The Simulator's state for a checkpoint and its restore (src/sim/checkpoint.cpp): every piece
// that a later step reads, so that a resumed run gives the uninterrupted run's bytes. Apart from
// simulator.cpp, which builds and steps the simulation.
#include <string>
#include <utility>

#include "collision/self_collision.hpp"
#include "collision/self_collision/common.hpp"
#include "shellcontract/error.hpp"
#include "sim/region_dimple.hpp"
#include "sim/simulator.hpp"

namespace shellcontract {

SimulatorState Simulator::state() const {
  SimulatorState s;
  s.frame = frame_;
  s.volume_ratio = volume_ratio_;
  s.stop_volume_reached = stop_volume_reached_;
  s.x = x_;
  s.v = v_;
  s.held_by_contact = held_by_contact_;
  for (const RegionDimple& d : region_dimples_) s.dimple_sizes.push_back(d.size);
  s.has_collision = collision_ != nullptr;
  if (collision_) s.collision = collision_->persistent_state();
  return s;
}

namespace {

/// Why `state` cannot be a persistent state of a SelfCollision of `t`, or empty if it can: a
/// contact whose pair is not one of this mesh's (an id out of range) or whose vertices are not
/// its pair's, a correction or skins not one per vertex. The warm start indexes the positions by
/// a contact's ids unchecked (a forged id crashed it).
std::string collision_state_problem(const SelfCollision::PersistentState& state,
                                    const CollisionTopology& t) {
  const auto faces = static_cast<std::size_t>(t.faces.rows());
  const auto edges = static_cast<std::size_t>(t.edges.rows());
  const auto vertices = static_cast<std::size_t>(t.num_vertices);
  const auto in = [](int id, std::size_t n) { return id >= 0 && static_cast<std::size_t>(id) < n; };
  for (std::size_t i = 0; i < state.contact_cache.size(); ++i) {
    const Contact& c = state.contact_cache[i];
    const std::string which = "contact " + std::to_string(i) + " of the contact cache ";
    const bool vf = c.kind == CcdPrimitive::VertexFace;
    if (!vf && c.kind != CcdPrimitive::EdgeEdge) return which + "is of no known kind";
    if (vf ? !in(c.pair[0], vertices) || !in(c.pair[1], faces)
           : !in(c.pair[0], edges) || !in(c.pair[1], edges))
      return which + "names " + (vf ? "vertex " : "edge ") + std::to_string(c.pair[0]) + " and " +
             (vf ? "face " : "edge ") + std::to_string(c.pair[1]) + "; the mesh has " +
             std::to_string(vertices) + " vertices, " + std::to_string(faces) + " faces and " +
             std::to_string(edges) + " edges";
    // The detection records a pair's vertices from the topology (stencil); a contact with
    // others would push vertices its pair does not hold.
    if (c.v != collision_pipeline::stencil(c.kind, c.pair, t))
      return which + "has vertices that are not those of its " +
             (vf ? "vertex and face" : "two edges");
  }
  if (state.correction.rows() != 0 && static_cast<std::size_t>(state.correction.rows()) != vertices)
    return "the broad phase's correction has " + std::to_string(state.correction.rows()) +
           " rows for " + std::to_string(vertices) + " vertices";
  if (state.skin.size() != 0 && static_cast<std::size_t>(state.skin.size()) != vertices)
    return "the broad phase's skins are " + std::to_string(state.skin.size()) + " for " +
           std::to_string(vertices) + " vertices";
  return {};
}

}  // namespace

void Simulator::restore(SimulatorState s) {
  const Eigen::Index n = x_.rows();
  const auto bad = [](const std::string& what) {
    throw InputError("the checkpoint does not fit this run: " + what);
  };
  if (s.x.rows() != n || s.x.cols() != 3 || s.v.rows() != n || s.v.cols() != 3)
    bad("it has " + std::to_string(s.x.rows()) + " vertices, the mesh " + std::to_string(n));
  if (!s.held_by_contact.empty() && s.held_by_contact.size() != static_cast<std::size_t>(n))
    bad("its contact marks are not one per vertex");
  if (s.dimple_sizes.size() != region_dimples_.size())
    bad("it has " + std::to_string(s.dimple_sizes.size()) + " region dimples, the run " +
        std::to_string(region_dimples_.size()));
  if (s.has_collision != (collision_ != nullptr)) bad("collisions on in one, off in the other");
  if (s.frame < 0) bad("a negative frame");
  // A run saves only while it goes on (run_contraction): a frame at or past its end, or a stop
  // ratio reached, is no state of this run (a frame past the end was reported as frames run).
  if (s.frame >= options_.frames)
    bad("its frame " + std::to_string(s.frame) + " is not before the run's end (" +
        std::to_string(options_.frames) + " frames)");
  if (s.stop_volume_reached) bad("it says the stop ratio was reached, so its run was over");
  for (std::size_t i = 0; i < region_dimples_.size(); ++i)
    if (s.dimple_sizes[i] < 0 ||
        static_cast<std::size_t>(s.dimple_sizes[i]) > region_dimples_[i].order.size())
      bad("region " + std::to_string(i) + "'s dimple has " + std::to_string(s.dimple_sizes[i]) +
          " faces; the region has " + std::to_string(region_dimples_[i].order.size()));
  if (collision_) {
    const std::string problem = collision_state_problem(s.collision, collision_->topology());
    if (!problem.empty()) bad(problem);
  }
  frame_ = s.frame;
  volume_ratio_ = s.volume_ratio;
  stop_volume_reached_ = s.stop_volume_reached;
  x_ = std::move(s.x);
  v_ = std::move(s.v);
  held_by_contact_ = std::move(s.held_by_contact);
  // Through resize_dimple, so that the dimples' rest shapes are those of the run that wrote it.
  for (std::size_t i = 0; i < region_dimples_.size(); ++i) resize_dimple(i, s.dimple_sizes[i]);
  if (collision_) collision_->restore_persistent_state(std::move(s.collision));
}

}  // namespace shellcontract
