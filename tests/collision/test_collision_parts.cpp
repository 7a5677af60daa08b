// The collision pipeline's parts on their own (docs/design/collision-pipeline.md): each contract
// checked against an oracle written here, one plain loop per rule, instead of through a whole
// SelfCollision step. Checked to fail when update keeps a pair's first detection or duplicates a
// pressed contact, when collect_live keeps excluded pairs, and when the zone leaves out the pairs
// that touch a zone vertex.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <random>
#include <vector>

#include "collision/self_collision/contact_cache.hpp"
#include "collision/self_collision/rescan.hpp"
#include "collision/self_collision/step_pairs.hpp"

namespace shellcontract::collision_pipeline {
namespace {

/// A VF contact of vertex p against face (a, b, c), normal +z, side +1, at the face point with
/// barycentric coordinates (1/3 + t, 1/3 - t, 1/3): the warm start pushes p to 2 delta above the
/// face if it is closer (and within the slide limit, 4 delta, of that point). t tells two
/// detections of the same pair apart.
Contact vf_contact(int p, int face, std::array<int, 3> abc, double t = 0.0) {
  Contact c;
  c.kind = CcdPrimitive::VertexFace;
  c.pair = {p, face};
  c.v = {p, abc[0], abc[1], abc[2]};
  c.weights = Eigen::Vector4d(1.0, -(1.0 / 3.0 + t), -(1.0 / 3.0 - t), -1.0 / 3.0);
  c.normal = Vec3::UnitZ();
  c.side = 1.0;
  return c;
}

/// An EE contact between edges (1, 2) and (5, 6) of two_stacks: 5 apart along the surface, so
/// the warm start leaves it (beyond the slide limit).
Contact ee_contact(int ea, int eb) {
  Contact c;
  c.kind = CcdPrimitive::EdgeEdge;
  c.pair = {ea, eb};
  c.v = {1, 2, 5, 6};
  c.weights = Eigen::Vector4d(1.0, 0.0, -1.0, 0.0);
  return c;
}

bool same_contact(const Contact& a, const Contact& b) {
  return a.kind == b.kind && a.pair == b.pair && a.v == b.v && a.weights == b.weights;
}

/// Two vertex-over-face configurations: vertex 0 over face (1, 2, 3), vertex 4 over face
/// (5, 6, 7), each at height h0 or h4 above its face's centroid (faces at z = 0).
Positions two_stacks(double h0, double h4) {
  Positions x = Positions::Zero(8, 3);
  x.row(1) << 0, 0, 0;
  x.row(2) << 1, 0, 0;
  x.row(3) << 0, 1, 0;
  x.row(0) << 1.0 / 3.0, 1.0 / 3.0, h0;
  x.row(5) << 5, 0, 0;
  x.row(6) << 6, 0, 0;
  x.row(7) << 5, 1, 0;
  x.row(4) << 16.0 / 3.0, 1.0 / 3.0, h4;
  return x;
}

TEST(CollisionParts, ContactCacheKeepsTheLastDetectionOfEachPairThenThePressedOnes) {
  // The next step's cache (ContactCache::update): the step's detections, one per pair (the last
  // one detected: its frame is the newest), ordered by pair (VF first), then the warm start's
  // pressed contacts whose pair was not detected again. Fails if update keeps the first
  // detection of a pair, drops or duplicates a pressed contact, or the warm start remembers a
  // contact it did not move.
  const double delta = 1e-3;
  ContactCache cache(delta);
  Eigen::VectorXd w = Eigen::VectorXd::Zero(8);
  w(0) = w(4) = 1.0;  // the faces pinned: a push moves the vertex alone, by the whole 2 delta
  const Contact a = vf_contact(0, 0, {1, 2, 3});
  const Contact b = vf_contact(4, 1, {5, 6, 7});
  cache.restore({a, b});

  // Step 1: vertex 0 lies on its face (pressed: the warm start pushes it), vertex 4 is far above.
  Positions x = two_stacks(0.0, 1.0);
  cache.warm_start(x, w);
  // The literal 2 (math-spec: contacts are pushed to 2 delta), not the code's RESPONSE_FACTOR:
  // a changed factor must fail here, not pass with it.
  EXPECT_DOUBLE_EQ(x(0, 2), 2.0 * delta);  // pushed to 2 delta
  EXPECT_DOUBLE_EQ(x(4, 2), 1.0);
  cache.clear_detections();
  EXPECT_TRUE(cache.contacts().empty());
  const Contact b1 = vf_contact(4, 1, {5, 6, 7}, 1e-4), b2 = vf_contact(4, 1, {5, 6, 7}, 2e-4);
  const Contact e = ee_contact(3, 9);
  cache.add_detections({b1, e});  // round 0
  cache.add_detections({b2});     // round 1: pair b again, a newer frame
  cache.update(8, 12);
  // Detections by pair (VF before EE), the last of each; then a, pressed and not detected.
  ASSERT_EQ(cache.contacts().size(), 3u);
  EXPECT_TRUE(same_contact(cache.contacts()[0], b2));
  EXPECT_TRUE(same_contact(cache.contacts()[1], e));
  EXPECT_TRUE(same_contact(cache.contacts()[2], a));

  // Step 2: both vertices on their faces, so a and b are pressed; a is detected again, b is not.
  x = two_stacks(0.0, 0.0);
  cache.warm_start(x, w);
  EXPECT_DOUBLE_EQ(x(0, 2), 2.0 * delta);
  EXPECT_DOUBLE_EQ(x(4, 2), 2.0 * delta);
  cache.clear_detections();
  const Contact a1 = vf_contact(0, 0, {1, 2, 3}, 3e-4);
  cache.add_detections({a1});
  cache.update(8, 12);
  // a once (its detection), then b2 (pressed, not detected); e is gone (neither).
  ASSERT_EQ(cache.contacts().size(), 2u);
  EXPECT_TRUE(same_contact(cache.contacts()[0], a1));
  EXPECT_TRUE(same_contact(cache.contacts()[1], b2));
}

/// n pairs with roles in a fixed pattern (all four roles, over several compaction blocks) and
/// stencils that name their index.
StepPairs patterned_pairs(std::size_t n) {
  StepPairs p;
  p.records.resize(n);
  p.role.resize(n);
  p.stale.resize(n);
  p.is_free.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const int k = static_cast<int>(i);
    p.records[i].kind = i % 3 == 0 ? CcdPrimitive::EdgeEdge : CcdPrimitive::VertexFace;
    p.records[i].pair = {(k * 7919) % 1000, k};
    p.records[i].v = {k, k + 1, k + 2, k + 3};
    p.role[i] = i % 7 == 3 ? EXCLUDED : i % 11 == 5 ? NOT_CANDIDATE : i % 5 == 0 ? NEAR : NORMAL;
    p.stale[i] = 0;
    p.is_free[i] = 1;
  }
  return p;
}

TEST(CollisionParts, TheLivePairsAreTheNormalAndNearPairsInOrderAtAnyThreadCount) {
  // StepPairs::collect_live: the pairs that may ever be tested (NORMAL or NEAR), in increasing
  // order, each with its stencil beside it, cut into units that cover them; live_consistent
  // accepts that and rejects a stencil out of step. candidate_pairs: every pair but the
  // speculative non-candidates, excluded ones included, each kind sorted.
  const std::size_t n = 20000;  // more than two compaction blocks
  std::vector<std::uint32_t> expected;
  for (std::size_t i = 0; i < n; ++i) {
    const bool live = !(i % 7 == 3) && !(i % 11 == 5);
    if (live) expected.push_back(static_cast<std::uint32_t>(i));
  }
  for (int threads : {1, 3}) {
    tbb::task_arena arena(threads);
    StepPairs p = patterned_pairs(n);
    p.collect_live(arena);
    ASSERT_EQ(p.live_count, expected.size()) << threads;
    std::vector<std::uint32_t> live;
    std::size_t covered = 0;
    for (const LiveUnit& u : p.live_units) {
      EXPECT_EQ(u.begin, covered);  // collect_live's units are contiguous from 0
      for (std::size_t j = u.begin; j < u.begin + u.count; ++j) {
        live.push_back(p.live[j]);
        EXPECT_EQ(p.live_v[j], p.records[p.live[j]].v);
      }
      covered += u.count;
    }
    EXPECT_EQ(live, expected) << threads;
    EXPECT_TRUE(p.live_consistent());
    p.live_v[p.live_count / 2][0] += 1;
    EXPECT_FALSE(p.live_consistent());
  }
  const StepPairs p = patterned_pairs(n);
  std::vector<std::array<int, 2>> vf, ee;
  for (std::size_t i = 0; i < n; ++i)
    if (p.role[i] != NOT_CANDIDATE)
      (p.records[i].kind == CcdPrimitive::VertexFace ? vf : ee).push_back(p.records[i].pair);
  std::sort(vf.begin(), vf.end());
  std::sort(ee.begin(), ee.end());
  const auto lists = p.candidate_pairs();
  EXPECT_EQ(lists.first, vf);
  EXPECT_EQ(lists.second, ee);
}

/// Random pairs over `vertices` vertices, with random roles, as a broad phase leaves them (stale
/// unless flagged far, free if not stale).
StepPairs random_pairs(std::size_t n, int vertices, std::mt19937& rng) {
  StepPairs p;
  p.records.resize(n);
  p.role.resize(n);
  p.stale.resize(n);
  p.is_free.resize(n);
  std::uniform_int_distribution<int> vertex(0, vertices - 1), percent(0, 99);
  for (std::size_t i = 0; i < n; ++i) {
    for (int& v : p.records[i].v) v = vertex(rng);
    const int r = percent(rng);
    p.role[i] = r < 5 ? EXCLUDED : r < 15 ? NEAR : NORMAL;
    p.stale[i] = p.role[i] != EXCLUDED && percent(rng) < 30;
    p.is_free[i] = !p.stale[i];
  }
  return p;
}

TEST(CollisionParts, RescanCollectsWhatItsRulesSayInTheZoneAsInFullPasses) {
  // Rescan::collect: marks stale every live pair with a vertex marked since the last pass, then
  // lists, in increasing order, the rounds' tests (stale and NORMAL) or the fail-safe's (stale or
  // not free, NORMAL or NEAR). Checked after every pass of a sequence of marks and tests (the
  // tests change the flags of the pairs they test, as Detection does), for a Rescan that visits
  // only the zone where it may and one that always visits every pair: both must match the rule.
  std::mt19937 rng(54);
  const int vertices = 3000;
  const std::size_t n = 20000;
  tbb::task_arena arena(2);
  const StepPairs start = random_pairs(n, vertices, rng);
  StepPairs zone_pairs = start, full_pairs = start, oracle = start;
  for (StepPairs* p : {&zone_pairs, &full_pairs, &oracle}) p->collect_live(arena);
  Rescan zone(vertices, true), full(vertices, false);
  zone.begin_step();
  full.begin_step();
  std::uniform_int_distribution<int> vertex(0, vertices - 1), percent(0, 99);
  CollisionStepStats zone_stats, full_stats;
  // Moves in a small set of vertices (the zone holds), then one elsewhere (a full pass again).
  std::vector<int> nearby;
  for (int k = 0; k < 4; ++k) nearby.push_back(vertex(rng));
  for (int pass = 0; pass < 12; ++pass) {
    const bool failsafe = pass >= 9;
    std::vector<int> moved;
    if (pass > 0) {
      const int count = 1 + percent(rng) % 5;
      for (int k = 0; k < count; ++k)
        moved.push_back(pass == 6 ? vertex(rng)
                                  : nearby[static_cast<std::size_t>(percent(rng)) % nearby.size()]);
    }
    for (int v : moved) {
      zone.mark(v);
      full.mark(v);
    }
    // The rule, on the oracle's flags.
    std::vector<std::uint32_t> expected;
    for (std::size_t i = 0; i < n; ++i) {
      if (oracle.role[i] >= EXCLUDED) continue;
      for (int v : moved)
        if (std::find(oracle.records[i].v.begin(), oracle.records[i].v.end(), v) !=
            oracle.records[i].v.end())
          oracle.stale[i] = 1;
      const bool keep = failsafe ? (oracle.stale[i] || !oracle.is_free[i])
                                 : (oracle.stale[i] && oracle.role[i] == NORMAL);
      if (keep) expected.push_back(static_cast<std::uint32_t>(i));
    }
    if (failsafe) {
      zone.collect<true>(arena, zone_pairs, zone_stats);
      full.collect<true>(arena, full_pairs, full_stats);
    } else {
      zone.collect<false>(arena, zone_pairs, zone_stats);
      full.collect<false>(arena, full_pairs, full_stats);
    }
    for (const StepPairs* p : {&zone_pairs, &full_pairs}) {
      const std::vector<std::uint32_t> got(p->tests.begin(), p->tests.begin() + p->test_count);
      EXPECT_EQ(got, expected) << "pass " << pass << (p == &zone_pairs ? " zone" : " full");
    }
    // The tests: no longer stale, free or hit at random (the same answers for all three).
    for (const std::uint32_t i : expected) {
      const std::uint8_t hit = percent(rng) < 20;
      for (StepPairs* p : {&zone_pairs, &full_pairs, &oracle}) {
        p->stale[i] = 0;
        p->is_free[i] = !hit;
      }
    }
  }
  EXPECT_EQ(zone_pairs.stale, oracle.stale);
  EXPECT_EQ(full_pairs.stale, oracle.stale);
  EXPECT_GT(zone_stats.rescans_in_zone, 0);  // the zone was used (else this proves nothing)
  EXPECT_EQ(full_stats.rescans_in_zone, 0);
}

}  // namespace
}  // namespace shellcontract::collision_pipeline
