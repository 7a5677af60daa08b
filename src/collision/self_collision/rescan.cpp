// The rescans: after a response push, the passes that mark the moved vertices' pairs stale and
// collect the next tests (in the zone around the moved vertices where that gives the same).
#include "collision/self_collision/rescan.hpp"

#include <type_traits>

namespace shellcontract::collision_pipeline {

void Rescan::begin_step() {
  for (int v : zone_vertices_) moved_[static_cast<std::size_t>(v)] &= ~ZONE;
  zone_vertices_.clear();
  zone_state_ = ZoneState::None;
}

template <bool FAILSAFE>
void Rescan::collect(tbb::task_arena& arena, StepPairs& pairs, CollisionStepStats& stats) {
  // One pass (one parallel region) over the live pairs marks the pairs of the moved vertices
  // stale and collects the next tests, one task per live unit. Raw pointers copied into
  // each task: through the byte stores to the stale flags the compiler would otherwise reload every
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
  // Work unit u is pairs.live_units[u]: its live pairs, and the slots from its begin in
  // pairs.tests and in the zone's lists.
  const std::size_t n = pairs.live_count;
  const std::size_t units = pairs.live_units.size();
  const std::size_t slots =
      units > 0 ? pairs.live_units.back().begin + pairs.live_units.back().count : 0;
  if (pairs.tests.size() < slots) resize_for_rewrite(pairs.tests, slots);
  block_count_.resize(units);
  const bool mark = !moved_list_.empty();
  bool in_zone = zone_state_ == ZoneState::Ready;
  for (std::size_t k = 0; in_zone && k < moved_list_.size(); ++k)
    in_zone = (moved_[static_cast<std::size_t>(moved_list_[k])] & ZONE) != 0;
  // A full pass that marks rebuilds the zone, grown by the vertices it marks (the zone only
  // grows: once too large, it stays so for the step).
  const bool build = !in_zone && mark && narrow_rescans_ && zone_state_ != ZoneState::TooLarge;
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
  const std::uint32_t* const live_data = in_zone ? zone_pair_.data() : pairs.live.data();
  const std::array<int, 4>* const live_v_data = in_zone ? zone_v_.data() : pairs.live_v.data();
  const std::size_t* const zone_counts = zone_count_.data();
  std::uint32_t* const zone_data = zone_pair_.data();
  std::array<int, 4>* const zone_v_data = zone_v_.data();
  std::size_t* const zone_count_data = zone_count_.data();
  const LiveUnit* const unit_data = pairs.live_units.data();
  const std::uint8_t* const moved_data = moved_.data();
  std::uint8_t* const stale_data = pairs.stale.data();
  const std::uint8_t* const role_data = pairs.role.data();
  const std::uint8_t* const free_data = pairs.is_free.data();
  std::uint32_t* const out_data = pairs.tests.data();
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
  arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, units, [&](std::size_t b) {
      if (build)
        pass(std::true_type{}, b);
      else
        pass(std::false_type{}, b);
    });
  });
  pairs.test_count = close_up(pairs.tests, pairs.live_units, block_count_);
  for (int v : moved_list_) moved_[static_cast<std::size_t>(v)] &= ~MOVED;
  moved_list_.clear();
  if (build) {
    // A zone of most of the pairs saves little: its passes would be nearly full ones.
    std::size_t total = 0;
    for (std::size_t b = 0; b < units; ++b) total += zone_count_[b];
    zone_state_ = total <= n / 2 ? ZoneState::Ready : ZoneState::TooLarge;
  }
}

template void Rescan::collect<false>(tbb::task_arena&, StepPairs&, CollisionStepStats&);
template void Rescan::collect<true>(tbb::task_arena&, StepPairs&, CollisionStepStats&);

}  // namespace shellcontract::collision_pipeline
