// The contact cache (CollisionOptions::warm_start): the warm start projects the last step's
// contacts on the end positions, and the step's detections and pressed contacts become the next
// step's cache.
#pragma once

#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "collision/contact.hpp"
#include "collision/self_collision/common.hpp"

namespace shellcontract::collision_pipeline {

/// Owns the cache the warm start projects and the buffers that rebuild it.
///
/// Over a step: warm_start (optional), then clear_detections, add_detections per round, then
/// update (optional). Between update and the next step's clear_detections, contacts() is the
/// cache; without update (no warm start) it is the step's detections as they came.
class ContactCache {
 public:
  /// delta: the contact distance; the warm start pushes to RESPONSE_FACTOR delta.
  explicit ContactCache(double delta) : delta_(delta) {}

  /// Projects the cache on the step's end positions x1 once and remembers those it moved (still
  /// pressed together) for update().
  void warm_start(Positions& x1, const Eigen::VectorXd& w) {
    pressed_.clear();
    project(x1, w, &pressed_);
  }
  /// The same projection on predicted end positions (SelfCollision::predict); remembers nothing.
  void warm_start_prediction(Positions& x, const Eigen::VectorXd& w) const {
    project(x, w, nullptr);
  }

  /// The cache is emptied; the step's detections are added to it in order (add_detections).
  void clear_detections() { contacts_.clear(); }
  void add_detections(const std::vector<Contact>& hits) {
    contacts_.insert(contacts_.end(), hits.begin(), hits.end());
  }

  /// The next step's cache: the step's detections (the last one of each pair) and the warm
  /// start's pressed contacts that were not detected again. `vertices` and `edges` size the
  /// lookup (the collision topology's).
  void update(std::size_t vertices, std::size_t edges);

  const std::vector<Contact>& contacts() const { return contacts_; }
  void restore(std::vector<Contact> contacts) { contacts_ = std::move(contacts); }

 private:
  /// Warm start: a previous contact is projected again only while its contact points have slid
  /// apart (tangentially) by at most this many push distances (RESPONSE_FACTOR delta each):
  /// farther, the frozen normal no longer describes the pair. A tighter limit drops resting
  /// contacts that then are detected and pushed again; no limit projects pairs whose normal has
  /// turned (the measured contact counts: lab/history.md, "Figures moved out of the collision
  /// pipeline's comments").
  ///
  /// The contacts the warm start projects are those of the last step: the ones detected then,
  /// and the ones its own warm start projected (update). With only the detected ones, a
  /// resting contact alternated: detected in one step, warm-started (so not detected) in the
  /// next, forgotten in the one after, detected again.
  static constexpr double WARM_START_SLIDE = 2.0;
  /// Projects contacts_ on x1 once; appends those it moved to `pressed` if given.
  void project(Positions& x1, const Eigen::VectorXd& w, std::vector<Contact>* pressed) const;

  /// End of a chain in update's lookup.
  static constexpr std::uint32_t NO_ENTRY = std::numeric_limits<std::uint32_t>::max();

  double delta_;
  /// The contact cache the warm start projects: during a step's rounds its detections,
  /// afterwards (update) also the pressed ones of the warm start, one per pair.
  std::vector<Contact> contacts_;
  std::vector<Contact> pressed_;  ///< this step's warm start moved them
  std::vector<Contact> next_;     ///< update's output buffer
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys_;  ///< (pair key, index)
  /// update's lookup of the detected pairs: per vertex (VF) and per edge (EE, the pair's first
  /// edge) the first of its detections in next_, then chain_ to the next one; NO_ENTRY ends a
  /// chain. All NO_ENTRY between calls.
  std::vector<std::uint32_t> head_vf_, head_ee_, chain_;
};

}  // namespace shellcontract::collision_pipeline
