// The contact cache: the warm start projects the last step's contacts on the end positions,
// and the step's detections and pressed contacts become the next step's cache.
#include "collision/self_collision/state.hpp"

namespace shellcontract {

void SelfCollision::Impl::warm_start(Positions& x1, const Eigen::VectorXd& w,
                                     std::vector<Contact>* pressed) const {
  const double separation = RESPONSE_FACTOR * options_.delta;
  for (const Contact& c : previous_contacts_) {
    // Trust the frozen contact frame only while the two contact points have not slid apart
    // along the surface by more than twice the push distance.
    Vec3 gap = Vec3::Zero();
    for (int k = 0; k < 4; ++k) gap += c.weights(k) * row(x1, c.v[static_cast<std::size_t>(k)]);
    if ((gap - gap.dot(c.normal) * c.normal).norm() > WARM_START_SLIDE * separation) continue;
    if (project_contact(c, separation, x1.data(), w.data()) && pressed != nullptr)
      pressed->push_back(c);
  }
}

void SelfCollision::Impl::update_contact_cache() {
  // A contact's pair as one key: kind, then the two ids (each < 2^31).
  auto key = [](const Contact& c) {
    return (c.kind == CcdPrimitive::EdgeEdge ? std::uint64_t{1} << 62 : std::uint64_t{0}) |
           static_cast<std::uint64_t>(c.pair[0]) << 31 | static_cast<std::uint64_t>(c.pair[1]);
  };
  // The step's detections, the last one of each pair (its frame is the newest), by key.
  cache_keys_.clear();
  for (std::size_t i = 0; i < previous_contacts_.size(); ++i)
    cache_keys_.emplace_back(key(previous_contacts_[i]), static_cast<std::uint32_t>(i));
  std::sort(cache_keys_.begin(), cache_keys_.end());
  cache_next_.clear();
  for (std::size_t i = 0; i < cache_keys_.size(); ++i)
    if (i + 1 == cache_keys_.size() || cache_keys_[i + 1].first != cache_keys_[i].first)
      cache_next_.push_back(previous_contacts_[cache_keys_[i].second]);
  // Then the warm start's pressed contacts whose pair was not detected again (they are unique:
  // a subset of the last cache). The detections are looked up through chains per vertex (VF)
  // and per first edge (EE), usually one entry long: a binary search over the sorted keys per
  // pressed contact was measurably slower at strong pressure (lab/history.md).
  const std::size_t detected = cache_next_.size();
  cache_head_vf_.resize(static_cast<std::size_t>(topo_.num_vertices), NO_ENTRY);
  cache_head_ee_.resize(static_cast<std::size_t>(topo_.edges.rows()), NO_ENTRY);
  cache_chain_.resize(detected);
  auto head = [&](const Contact& c) -> std::uint32_t& {
    std::vector<std::uint32_t>& heads =
        c.kind == CcdPrimitive::VertexFace ? cache_head_vf_ : cache_head_ee_;
    return heads[static_cast<std::size_t>(c.pair[0])];
  };
  for (std::size_t i = 0; i < detected; ++i) {
    std::uint32_t& first = head(cache_next_[i]);
    cache_chain_[i] = first;
    first = static_cast<std::uint32_t>(i);
  }
  for (const Contact& c : pressed_contacts_) {
    bool found = false;
    for (std::uint32_t i = head(c); i != NO_ENTRY && !found; i = cache_chain_[i])
      found = cache_next_[i].kind == c.kind && cache_next_[i].pair == c.pair;
    if (!found) cache_next_.push_back(c);
  }
  for (std::size_t i = 0; i < detected; ++i) head(cache_next_[i]) = NO_ENTRY;
  previous_contacts_.swap(cache_next_);
}

}  // namespace shellcontract
