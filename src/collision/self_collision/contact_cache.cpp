// The contact cache: the warm start projects the last step's contacts on the end positions,
// and the step's detections and pressed contacts become the next step's cache.
#include "collision/self_collision/contact_cache.hpp"

#include <algorithm>

namespace shellcontract::collision_pipeline {

void ContactCache::project(Positions& x1, const Eigen::VectorXd& w,
                           std::vector<Contact>* pressed) const {
  const double separation = RESPONSE_FACTOR * delta_;
  for (const Contact& c : contacts_) {
    // Trust the frozen contact frame only while the two contact points have not slid apart
    // along the surface by more than twice the push distance.
    Vec3 gap = Vec3::Zero();
    for (int k = 0; k < 4; ++k) gap += c.weights(k) * row(x1, c.v[static_cast<std::size_t>(k)]);
    if ((gap - gap.dot(c.normal) * c.normal).norm() > WARM_START_SLIDE * separation) continue;
    if (project_contact(c, separation, x1.data(), w.data()) && pressed != nullptr)
      pressed->push_back(c);
  }
}

void ContactCache::update(std::size_t vertices, std::size_t edges) {
  // A contact's pair as one key: kind, then the two ids (each < 2^31).
  auto key = [](const Contact& c) {
    return (c.kind == CcdPrimitive::EdgeEdge ? std::uint64_t{1} << 62 : std::uint64_t{0}) |
           static_cast<std::uint64_t>(c.pair[0]) << 31 | static_cast<std::uint64_t>(c.pair[1]);
  };
  // The step's detections, the last one of each pair (its frame is the newest), by key.
  keys_.clear();
  for (std::size_t i = 0; i < contacts_.size(); ++i)
    keys_.emplace_back(key(contacts_[i]), static_cast<std::uint32_t>(i));
  std::sort(keys_.begin(), keys_.end());
  next_.clear();
  for (std::size_t i = 0; i < keys_.size(); ++i)
    if (i + 1 == keys_.size() || keys_[i + 1].first != keys_[i].first)
      next_.push_back(contacts_[keys_[i].second]);
  // Then the warm start's pressed contacts whose pair was not detected again (they are unique:
  // a subset of the last cache). The detections are looked up through chains per vertex (VF)
  // and per first edge (EE), usually one entry long: a binary search over the sorted keys per
  // pressed contact was measurably slower at strong pressure (lab/history.md).
  const std::size_t detected = next_.size();
  head_vf_.resize(vertices, NO_ENTRY);
  head_ee_.resize(edges, NO_ENTRY);
  chain_.resize(detected);
  auto head = [&](const Contact& c) -> std::uint32_t& {
    std::vector<std::uint32_t>& heads = c.kind == CcdPrimitive::VertexFace ? head_vf_ : head_ee_;
    return heads[static_cast<std::size_t>(c.pair[0])];
  };
  for (std::size_t i = 0; i < detected; ++i) {
    std::uint32_t& first = head(next_[i]);
    chain_[i] = first;
    first = static_cast<std::uint32_t>(i);
  }
  for (const Contact& c : pressed_) {
    bool found = false;
    for (std::uint32_t i = head(c); i != NO_ENTRY && !found; i = chain_[i])
      found = next_[i].kind == c.kind && next_[i].pair == c.pair;
    if (!found) next_.push_back(c);
  }
  for (std::size_t i = 0; i < detected; ++i) head(next_[i]) = NO_ENTRY;
  contacts_.swap(next_);
}

}  // namespace shellcontract::collision_pipeline
