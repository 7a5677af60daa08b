// The live pairs and the rescans: after a response push, the passes that mark the moved
// vertices' pairs stale and collect the next tests (in the zone around the moved vertices where
// that gives the same).
#include "collision/self_collision/state.hpp"

namespace shellcontract {

bool SelfCollision::Impl::live_pairs_consistent() const {
  std::size_t count = 0, next = 0;
  bool first = true;
  std::uint32_t last = 0;
  for (const LiveUnit& u : live_units_) {
    if (u.begin < next || u.begin + u.count > live_.size() || u.begin + u.count > live_v_.size())
      return false;
    next = u.begin + u.count;
    for (std::size_t j = u.begin; j < next; ++j) {
      const std::uint32_t i = live_[j];
      if (i >= pairs_.size() || i >= role_.size() || role_[i] >= EXCLUDED) return false;
      if (!first && last >= i) return false;
      if (live_v_[j] != pairs_[i].v) return false;
      first = false;
      last = i;
    }
    count += u.count;
  }
  return count == live_count_;
}

template <class Keep>
std::size_t SelfCollision::Impl::compact(std::size_t n, Keep keep,
                                         PairArray<std::uint32_t>& out) {
  // Fixed blocks (never cut by the thread count): block b compacts its kept indices, in order,
  // to the front of its own slice out[b B, (b + 1) B); the slices are then closed up in order.
  constexpr std::size_t B = COMPACT_BLOCK;
  const std::size_t blocks = (n + B - 1) / B;
  if (out.size() < n) resize_for_rewrite(out, n);
  block_count_.resize(blocks);
  workers_->arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      std::uint32_t* dst = out.data() + b * B;
      const std::size_t end = std::min(n, (b + 1) * B);
      std::size_t k = 0;
      for (std::size_t i = b * B; i < end; ++i) {
        dst[k] = static_cast<std::uint32_t>(i);  // branch-free: keep() is hard to predict
        k += keep(i) ? 1 : 0;
      }
      block_count_[b] = k;
    });
  });
  return close_up(out, B, block_count_);
}

std::size_t SelfCollision::Impl::close_up(PairArray<std::uint32_t>& out,
                                          const std::vector<LiveUnit>& units,
                                          const std::vector<std::size_t>& counts) {
  std::size_t total = 0;
  for (std::size_t u = 0; u < units.size(); ++u) {
    if (total != units[u].begin)
      std::memmove(out.data() + total, out.data() + units[u].begin,
                   counts[u] * sizeof(std::uint32_t));
    total += counts[u];
  }
  return total;
}

void SelfCollision::Impl::collect_live() {
  live_count_ = compact(
      pairs_.size(), [&](std::size_t i) { return role_[i] < EXCLUDED; }, live_);
  if (live_v_.size() < live_count_) resize_for_rewrite(live_v_, live_count_);
  workers_->arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, live_count_, PAIR_GRAIN),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t j = r.begin(); j < r.end(); ++j)
                          live_v_[j] = pairs_[live_[j]].v;
                      });
  });
  set_live_units(live_count_);
}

void SelfCollision::Impl::set_live_units(std::size_t count) {
  live_count_ = count;
  live_units_.clear();
  for (std::size_t b = 0; b < live_count_; b += COMPACT_BLOCK)
    live_units_.push_back(LiveUnit{b, std::min(COMPACT_BLOCK, live_count_ - b)});
}

template <bool FAILSAFE>
void SelfCollision::Impl::mark_moved_and_collect(CollisionStepStats& stats) {
  // One pass (one parallel region) over the live pairs marks the pairs of the moved vertices
  // stale and collects the next tests, one task per live unit. Raw pointers copied into
  // each task: through the byte stores to stale_ the compiler would otherwise reload every
  // vector's data pointer per pair.
  //
  // The zone (CollisionOptions::narrow_rescans): a full pass that marks also lists, per unit,
  // the live pairs that touch a zone vertex (one that a push or a revert has moved since the
  // step began, this pass's included) or are stale or not free after it. Until a vertex outside
  // the zone moves, every later pass visits only those: a pair outside touches no vertex that
  // has moved since, so its flags stay as the full pass left them (not stale, free) and no pass
  // would mark or collect it; the tested pairs, the only ones detect changes, are collected
  // ones. The zone pass collects the same pairs in the same order. Why: at strong pressure a
  // full pass over the live pairs costs far more than the few tests the later rounds collect,
  // and a good share of the passes stay in the zone (measured on bear at P = 4;
  // lab/history.md).
  //
  // Work unit u is live_units_[u]: its live pairs, and the slots from its begin in tests_ and
  // in the zone's lists.
  const std::size_t n = live_count_;
  const std::size_t units = live_units_.size();
  const std::size_t slots = units > 0 ? live_units_.back().begin + live_units_.back().count : 0;
  if (tests_.size() < slots) resize_for_rewrite(tests_, slots);
  block_count_.resize(units);
  const bool mark = !moved_list_.empty();
  bool in_zone = zone_state_ == ZoneState::Ready;
  for (std::size_t k = 0; in_zone && k < moved_list_.size(); ++k)
    in_zone = (moved_[static_cast<std::size_t>(moved_list_[k])] & ZONE) != 0;
  // A full pass that marks rebuilds the zone, grown by the vertices it marks (the zone only
  // grows: once too large, it stays so for the step).
  const bool build =
      !in_zone && mark && options_.narrow_rescans && zone_state_ != ZoneState::TooLarge;
  if (build) {
    // The build pass rewrites the zone whole: its growth neither zeroes nor copies. As
    // std::vector's, on one thread, the growth showed in perf on the largest meshes (the pairs
    // grow as the shell contracts; lab/history.md).
    if (zone_pair_.size() < slots) resize_for_rewrite(zone_pair_, slots);
    if (zone_v_.size() < slots) resize_for_rewrite(zone_v_, slots);
    zone_count_.resize(units);
    for (int v : moved_list_) {
      std::uint8_t& f = moved_[static_cast<std::size_t>(v)];
      if (!(f & ZONE)) zone_vertices_.push_back(v);
      f |= ZONE;
    }
  }
  ++(in_zone ? stats.rescans_in_zone : stats.rescans_full);
  const std::uint32_t* const live_data = in_zone ? zone_pair_.data() : live_.data();
  const std::array<int, 4>* const live_v_data = in_zone ? zone_v_.data() : live_v_.data();
  const std::size_t* const zone_counts = zone_count_.data();
  std::uint32_t* const zone_data = zone_pair_.data();
  std::array<int, 4>* const zone_v_data = zone_v_.data();
  std::size_t* const zone_count_data = zone_count_.data();
  const LiveUnit* const unit_data = live_units_.data();
  const std::uint8_t* const moved_data = moved_.data();
  std::uint8_t* const stale_data = stale_.data();
  const std::uint8_t* const role_data = role_.data();
  const std::uint8_t* const free_data = free_.data();
  std::uint32_t* const out_data = tests_.data();
  std::size_t* const count_data = block_count_.data();
  auto pass = [=](auto build_tag, std::size_t b) {
    constexpr bool BUILD = decltype(build_tag)::value;
    // A zone pass visits unit b's zone entries, a full pass its live pairs.
    const std::size_t at = unit_data[b].begin;
    const std::uint32_t* __restrict live = live_data + at;
    const std::array<int, 4>* __restrict live_v = live_v_data + at;
    const std::size_t count = in_zone ? zone_counts[b] : unit_data[b].count;
    const std::uint8_t* __restrict moved = moved_data;
    std::uint8_t* __restrict stale = stale_data;
    const std::uint8_t* __restrict role = role_data;
    const std::uint8_t* __restrict fr = free_data;
    std::uint32_t* __restrict dst = out_data + at;
    std::uint32_t* __restrict zone = zone_data + at;
    std::array<int, 4>* __restrict zone_v = zone_v_data + at;
    std::size_t k = 0, z = 0;
    for (std::size_t j = 0; j < count; ++j) {
      const std::uint32_t i = live[j];
      std::uint8_t st = stale[i], touch = 0;
      if (mark) {
        const std::array<int, 4>& v = live_v[j];
        touch = moved[static_cast<std::size_t>(v[0])] | moved[static_cast<std::size_t>(v[1])] |
                moved[static_cast<std::size_t>(v[2])] | moved[static_cast<std::size_t>(v[3])];
        st |= touch & MOVED;
        stale[i] = st;
      }
      const std::uint8_t unfree = fr[i] ^ 1;
      // Rounds: stale NORMAL pairs (no push for pairs near at rest). Fail-safe: every live
      // pair not known to be free at its current positions (stale, hit, or near at rest).
      const bool keep =
          FAILSAFE ? ((st | unfree) & (role[i] < EXCLUDED)) != 0 : (st & (role[i] == NORMAL)) != 0;
      dst[k] = i;  // branch-free: keep is hard to predict
      k += keep ? 1 : 0;
      if (BUILD) {
        zone[z] = i;
        zone_v[z] = live_v[j];
        z += ((touch & ZONE) | st | unfree) != 0 ? 1 : 0;
      }
    }
    count_data[b] = k;
    if (BUILD) zone_count_data[b] = z;
  };
  workers_->arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, units, [&](std::size_t b) {
      if (build)
        pass(std::true_type{}, b);
      else
        pass(std::false_type{}, b);
    });
  });
  test_count_ = close_up(tests_, live_units_, block_count_);
  for (int v : moved_list_) moved_[static_cast<std::size_t>(v)] &= ~MOVED;
  moved_list_.clear();
  if (build) {
    // A zone of most of the pairs saves little: its passes would be nearly full ones.
    std::size_t total = 0;
    for (std::size_t b = 0; b < units; ++b) total += zone_count_[b];
    zone_state_ = total <= n / 2 ? ZoneState::Ready : ZoneState::TooLarge;
  }
}

template void SelfCollision::Impl::mark_moved_and_collect<false>(CollisionStepStats& stats);
template void SelfCollision::Impl::mark_moved_and_collect<true>(CollisionStepStats& stats);

}  // namespace shellcontract
