// The per-step collision pipeline on spheres against brute force (math-spec 10.8, 13 "CCD" last
// item; issue "self-collision" items 4-5): the response stays in its boxes, the contact cache,
// crushed and flattened spheres that never touch themselves, results for any thread count,
// speculation and narrow rescans. Two-triangle cases are test_self_collision.cpp's.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <tuple>

#include "collision/broad_phase.hpp"
#include "collision/ccd.hpp"
#include "collision/contact.hpp"
#include "collision/self_collision.hpp"
#include "shellcontract/error.hpp"
#include "support/mesh_fixtures.hpp"


namespace shellcontract {
namespace {

/// box_cull: skip the pairs swept_boxes_apart (tested on its own in test_ccd_filters.cpp) shows
/// apart, which makes a larger mesh affordable but makes the oracle share that function with the
/// code under test; the small-sphere tests run without it.
int brute_force_contacts(const Faces& faces, const Positions& x0, const Positions& x1,
                         bool box_cull = false) {
  const CollisionTopology topo = make_collision_topology(faces, static_cast<int>(x0.rows()));
  auto X = [](const Positions& x, int i) { return Vec3(x.row(i).transpose()); };
  auto stencils = [&](const std::array<int, 4>& v, CcdStencil& s0, CcdStencil& s1) {
    for (int k = 0; k < 4; ++k) {
      s0[static_cast<std::size_t>(k)] = X(x0, v[static_cast<std::size_t>(k)]);
      s1[static_cast<std::size_t>(k)] = X(x1, v[static_cast<std::size_t>(k)]);
    }
  };
  int hits = 0;
  CcdStencil s0, s1;
  for (int v = 0; v < x0.rows(); ++v)
    for (Eigen::Index f = 0; f < faces.rows(); ++f) {
      if (faces(f, 0) == v || faces(f, 1) == v || faces(f, 2) == v) continue;
      stencils({v, faces(f, 0), faces(f, 1), faces(f, 2)}, s0, s1);
      if (box_cull && swept_boxes_apart(CcdPrimitive::VertexFace, s0, s1, 0.0)) continue;
      hits += vertex_face_ccd(s0, s1).hit;
    }
  for (Eigen::Index a = 0; a < topo.edges.rows(); ++a)
    for (Eigen::Index b = a + 1; b < topo.edges.rows(); ++b) {
      const std::array<int, 4> v{topo.edges(a, 0), topo.edges(a, 1), topo.edges(b, 0), topo.edges(b, 1)};
      if (v[0] == v[2] || v[0] == v[3] || v[1] == v[2] || v[1] == v[3]) continue;
      stencils(v, s0, s1);
      if (box_cull && swept_boxes_apart(CcdPrimitive::EdgeEdge, s0, s1, 0.0)) continue;
      hits += edge_edge_ccd(s0, s1).hit;
    }
  return hits;
}

/// A solver's guess for a step ending at x1 with speculation on: x1 off by a little everywhere
/// and by a lot at every 7th vertex (outside its predicted box).
Positions guess_for(const Positions& x1, std::mt19937& rng) {
  std::uniform_real_distribution<double> small(-2e-4, 2e-4);
  Positions g = x1;
  for (Eigen::Index i = 0; i < g.rows(); ++i)
    for (int d = 0; d < 3; ++d) g(i, d) += i % 7 == 0 ? 0.05 : small(rng);
  return g;
}

/// Collision steps on a level-`level` icosphere with delta 1e-3: each step ends at
/// move(x0, rng); with `speculative`, predict() gets guess_for(x1) first. Asserts that no pair
/// touches after a step (brute force) if `brute_force`. Returns the positions after each step.
template <class Move>
std::vector<Positions> sphere_steps(CollisionOptions opt, int level, unsigned seed, int steps,
                                    Move move, bool speculative, bool brute_force,
                                    std::vector<CollisionStepStats>* all_stats) {
  const test::TriMesh sphere = test::icosphere(level);
  opt.delta = 1e-3;
  SelfCollision sc(sphere.faces, sphere.x, opt);
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(sphere.x.rows());
  std::mt19937 rng(seed);
  Positions x0 = sphere.x;
  std::vector<Positions> out;
  for (int step = 0; step < steps; ++step) {
    Positions x1 = move(x0, rng);
    CollisionStepStats stats;
    if (speculative) sc.predict(x0, guess_for(x1, rng), w);
    sc.resolve(x0, x1, w, stats);
    if (all_stats) all_stats->push_back(stats);
    if (brute_force) {
      EXPECT_EQ(brute_force_contacts(sphere.faces, x0, x1, level > 2), 0) << "step " << step;
    }
    out.push_back(x1);
    x0 = x1;
  }
  return out;
}

/// Steps of a sphere crushed flat through itself with random jitter: every step's motion makes
/// the top pass through the bottom and many pairs cross, so the response pushes vertices far
/// (more than the reuse margin: the re-broad-phase path runs) and the incremental rounds and
/// fail-safe must find every pair. Returns the positions after each step.
std::vector<Positions> crush_sphere(int threads, int rounds, bool warm_start,
                                    std::vector<CollisionStepStats>* all_stats, int level = 2,
                                    bool brute_force = true, bool speculative = false,
                                    bool narrow_rescans = true) {
  CollisionOptions opt;
  opt.threads = threads;
  opt.rounds = rounds;
  opt.warm_start = warm_start;
  opt.narrow_rescans = narrow_rescans;
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  auto move = [&](const Positions& x0, std::mt19937& rng) {
    Positions x1 = x0;
    for (Eigen::Index i = 0; i < x1.rows(); ++i) {
      x1(i, 2) = -0.6 * x0(i, 2);  // the poles swap sides: top and bottom pass through
      for (int d = 0; d < 3; ++d) x1(i, d) += jitter(rng);
    }
    return x1;
  };
  return sphere_steps(opt, level, 7, 6, move, speculative, brute_force, all_stats);
}

TEST(SelfCollision, ResponseKeepsEveryVertexInItsSweptBoxGrownByHalfTheMargin) {
  // The one-broad-phase-per-step scheme relies on it: after resolve, each vertex lies within
  // m/2 of the box of its start and (given) end position. The crushed sphere pushes vertices
  // far (without the clamp they leave their boxes by several delta).
  const test::TriMesh sphere = test::icosphere(2);
  CollisionOptions opt;
  opt.delta = 1e-3;
  opt.warm_start = false;  // the warm start moves x1 before the boxes are taken
  SelfCollision sc(sphere.faces, sphere.x, opt);
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(sphere.x.rows());
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  Positions x0 = sphere.x;
  std::int64_t contacts = 0;
  for (int step = 0; step < 4; ++step) {
    Positions x1 = x0;
    for (Eigen::Index i = 0; i < x1.rows(); ++i) {
      x1(i, 2) = -0.6 * x0(i, 2);
      for (int d = 0; d < 3; ++d) x1(i, d) += jitter(rng);
    }
    const Positions given = x1;
    CollisionStepStats stats;
    sc.resolve(x0, x1, w, stats);
    contacts += stats.contacts;
    const double slack = 0.5 * opt.region_margin * opt.delta * (1.0 + 1e-9);
    for (Eigen::Index i = 0; i < x1.rows(); ++i)
      for (int d = 0; d < 3; ++d) {
        ASSERT_GE(x1(i, d), std::min(x0(i, d), given(i, d)) - slack) << "step " << step << " vertex " << i;
        ASSERT_LE(x1(i, d), std::max(x0(i, d), given(i, d)) + slack) << "step " << step << " vertex " << i;
      }
    x0 = x1;
  }
  EXPECT_GT(contacts, 100);
}

TEST(SelfCollision, ContactCacheHoldsOnePerPairOfTheDetectionsAndThePressed) {
  // A sphere flattened until its halves rest on each other, with the warm start: the cache
  // holds the step's detections and the contacts its warm start pushed, each pair once (a
  // pressed pair detected again keeps only the detection, whose frame is newer), and pairs are
  // carried from step to step.
  const test::TriMesh sphere = test::icosphere(2);
  CollisionOptions opt;
  opt.delta = 1e-3;
  SelfCollision sc(sphere.faces, sphere.x, opt);
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(sphere.x.rows());
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> jitter(-1e-4, 1e-4);
  Positions x0 = sphere.x;
  auto key = [](const Contact& c) {
    return std::make_tuple(c.kind == CcdPrimitive::EdgeEdge, c.pair[0], c.pair[1]);
  };
  std::size_t cached = 0, carried = 0;
  for (int step = 0; step < 12; ++step) {
    SCOPED_TRACE("step " + std::to_string(step));
    const std::vector<Contact> before = sc.contact_cache();
    Positions x1 = x0;
    for (Eigen::Index i = 0; i < x1.rows(); ++i) {
      // Flattened towards z = 0 until the two halves press on each other.
      x1(i, 2) = 0.3 * x0(i, 2);
      for (int d = 0; d < 3; ++d) x1(i, d) += jitter(rng);
    }
    CollisionStepStats stats;
    sc.resolve(x0, x1, w, stats);
    std::vector<std::tuple<bool, int, int>> keys;
    for (const Contact& c : sc.contact_cache()) keys.push_back(key(c));
    std::sort(keys.begin(), keys.end());
    EXPECT_TRUE(std::adjacent_find(keys.begin(), keys.end()) == keys.end()) << "a pair twice";
    // Pairs of the last cache kept (pressed again, or detected again) are part of the new one.
    for (const Contact& c : before)
      carried += std::binary_search(keys.begin(), keys.end(), key(c)) ? 1u : 0u;
    cached += keys.size();
    x0 = x1;
  }
  EXPECT_GT(cached, 0u);
  EXPECT_GT(carried, 0u);
}

TEST(SelfCollision, CrushedSphereNeverTouchesItselfAndRunsDoNotDependOnThreads) {
  for (const bool warm : {true, false})
  for (int rounds : {5, 1}) {
    SCOPED_TRACE("rounds " + std::to_string(rounds) + (warm ? ", warm start" : ""));
    std::vector<CollisionStepStats> stats;
    const std::vector<Positions> one = crush_sphere(1, rounds, warm, &stats);
    std::int64_t contacts = 0, failsafe = 0, axis_culls = 0;
    int multi_round = 0;
    for (const CollisionStepStats& s : stats) {
      contacts += s.contacts;
      failsafe += s.failsafe_vertices;
      multi_round += s.rounds > 1;
      axis_culls += s.axis_culls;
      EXPECT_EQ(s.broad_phase_calls, 1);
      // Queries the separating-axis test settles are part of the narrow phase's queries, which
      // are the filter's survivors, which are part of its tests.
      EXPECT_LE(s.axis_culls, s.narrow_tests);
      EXPECT_LE(s.narrow_tests, s.filter_tests);
      EXPECT_LE(s.pairs_filtered, s.pairs_broad);
      // The reported collision time is the whole call, which contains the disjoint stage
      // intervals (the factor only absorbs the rounding of the sums of durations to double).
      EXPECT_GE(s.seconds * (1.0 + 1e-12),
                s.broad_seconds + s.filter_seconds + s.narrow_seconds + s.response_seconds);
    }
    // The scenario exercises every path: response rounds (incremental after round 0) and the
    // fail-safe (1 round is too few to resolve every crossing).
    EXPECT_GT(contacts, 0);
    EXPECT_GT(axis_culls, 0);
    if (rounds > 1) {
      EXPECT_GT(multi_round, 0);
    } else {
      EXPECT_GT(failsafe, 0);
    }
    const std::vector<Positions> two = crush_sphere(2, rounds, warm, nullptr);
    ASSERT_EQ(one.size(), two.size());
    for (std::size_t i = 0; i < one.size(); ++i) EXPECT_EQ(one[i], two[i]) << "step " << i;
  }
}

TEST(SelfCollision, SpeculativeBroadPhaseHasThePlainCandidates) {
  // predict() builds the grid on predicted boxes; resolve() must end up with exactly the pairs
  // of find_candidates on the actual step, whether a vertex stayed in its predicted box, left
  // it, or (with its neighbours) left it together with the primitives around it.
  const test::TriMesh sphere = test::icosphere(2);
  const Eigen::Index n = sphere.x.rows();
  CollisionOptions opt;
  opt.delta = 1e-3;
  opt.warm_start = false;  // then the broad phase sees the given x1
  SelfCollision sc(sphere.faces, sphere.x, opt);
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(n);
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> motion(-0.01, 0.01), small(-5e-4, 5e-4);
  Positions x0 = sphere.x;
  std::int64_t escaped = 0;
  int speculative = 0, clean = 0;
  for (int step = 0; step < 12; ++step) {
    SCOPED_TRACE("step " + std::to_string(step));
    Positions x1 = x0, guess = x0;
    for (Eigen::Index i = 0; i < n; ++i) {
      x1(i, 2) -= 0.04 * x0(i, 2);  // flatten towards z = 0
      for (int d = 0; d < 3; ++d) x1(i, d) += motion(rng);
      for (int d = 0; d < 3; ++d) guess(i, d) = x1(i, d) + small(rng);
      // A cap of neighbouring vertices far off its guess in some steps (the primitives between
      // them leave together), a lone vertex in others, none in the rest.
      if ((step % 3 == 1 && x0(i, 0) > 0.8) || (step % 3 == 2 && i == 5)) guess(i, 1) += 0.03;
    }
    if (step == 11) guess.array() += 0.1;  // every vertex off: the plain broad phase runs
    CandidatePairs expected;
    const double max_abs = std::max(x0.cwiseAbs().maxCoeff(), x1.cwiseAbs().maxCoeff());
    find_candidates(x0, x1, sc.topology(), broad_phase_inflation(opt, max_abs), expected);
    std::sort(expected.vertex_face.begin(), expected.vertex_face.end());
    std::sort(expected.edge_edge.begin(), expected.edge_edge.end());
    CollisionStepStats stats;
    sc.predict(x0, guess, w);
    Positions x = x1;
    sc.resolve(x0, x, w, stats);
    const auto got = sc.candidate_pairs();
    EXPECT_TRUE(sc.live_pairs_consistent());
    using List = std::vector<std::array<int, 2>>;  // candidate_pairs()' type
    EXPECT_EQ(got.first, List(expected.vertex_face.begin(), expected.vertex_face.end()));
    EXPECT_EQ(got.second, List(expected.edge_edge.begin(), expected.edge_edge.end()));
    EXPECT_EQ(stats.pairs_broad, static_cast<std::int64_t>(expected.vertex_face.size() +
                                                           expected.edge_edge.size()));
    EXPECT_EQ(stats.speculative, step == 11 ? 0 : 1);
    speculative += stats.speculative;
    escaped += stats.escaped_vertices;
    clean += stats.speculative == 1 && stats.escaped_vertices == 0;
    x0 = x;
  }
  EXPECT_EQ(speculative, 11);
  EXPECT_GT(escaped, 20);  // the caps
  EXPECT_GT(clean, 0);     // steps whose guesses held everywhere
  // A prediction for another x0 is not used.
  sc.predict(x0, x0, w);
  Positions moved = x0;
  moved.array() += 1e-3;
  Positions x = moved;
  CollisionStepStats stats;
  sc.resolve(moved, x, w, stats);
  EXPECT_EQ(stats.speculative, 0);
  // A guess with a NaN or infinite coordinate makes no prediction (a NaN would leave its box
  // finite: std::min and std::max pass the other argument): the plain broad phase runs.
  for (const double bad_value :
       {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    Positions guess = x0;
    guess(n / 2, 1) = bad_value;
    sc.predict(x0, guess, w);
    x = x0;
    sc.resolve(x0, x, w, stats);
    EXPECT_EQ(stats.speculative, 0) << bad_value;
    EXPECT_TRUE(x.allFinite());
  }
  EXPECT_THROW(sc.predict(x0, Positions(n + 1, 3), w), UsageError);
  // After a prediction, arrays that do not match the mesh are still reported, not read.
  sc.predict(x0, x0, w);
  Positions bad = Positions::Zero(n + 1, 3), bad0 = bad;
  EXPECT_THROW(sc.resolve(bad0, bad, w, stats), UsageError);
}

/// A sphere flattened onto itself (z shrinks by 45% a step, with jitter) with speculation on:
/// the guess is the end position off by a little, and by a lot at every 7th vertex.
std::vector<Positions> flatten_sphere_speculatively(int threads, bool warm_start,
                                                    std::vector<CollisionStepStats>& all_stats) {
  CollisionOptions opt;
  opt.threads = threads;
  opt.warm_start = warm_start;
  std::uniform_real_distribution<double> jitter(-0.01, 0.01);
  auto move = [&](const Positions& x0, std::mt19937& rng) {
    Positions x1 = x0;
    for (Eigen::Index i = 0; i < x1.rows(); ++i) {
      x1(i, 2) = 0.55 * x0(i, 2);
      for (int d = 0; d < 3; ++d) x1(i, d) += jitter(rng);
    }
    return x1;
  };
  return sphere_steps(opt, 2, 3, 14, move, true, true, &all_stats);
}

TEST(SelfCollision, SpeculativeFlattenedSphereNeverTouchesItselfAndDoesNotDependOnThreads) {
  for (const bool warm : {true, false}) {
    SCOPED_TRACE(warm ? "warm start" : "no warm start");
    std::vector<CollisionStepStats> stats, stats2;
    const std::vector<Positions> one = flatten_sphere_speculatively(1, warm, stats);
    std::int64_t escaped = 0, contacts = 0;
    int speculative = 0;
    for (const CollisionStepStats& s : stats) {
      speculative += s.speculative;
      escaped += s.escaped_vertices;
      contacts += s.contacts;
    }
    // The scenario exercises the speculative path with vertices outside their predicted boxes
    // and with contacts to resolve.
    EXPECT_GT(speculative, 7);
    EXPECT_GT(escaped, 0);
    EXPECT_GT(contacts, 0);
    const std::vector<Positions> two = flatten_sphere_speculatively(2, warm, stats2);
    ASSERT_EQ(one.size(), two.size());
    for (std::size_t i = 0; i < one.size(); ++i) EXPECT_EQ(one[i], two[i]) << "step " << i;
    for (std::size_t i = 0; i < stats.size(); ++i) {
      EXPECT_EQ(stats[i].speculative, stats2[i].speculative);
      EXPECT_EQ(stats[i].pairs_broad, stats2[i].pairs_broad);
      // The time the task still cost the step is part of the broad phase's, which is part of
      // the step's collision time. (Durations are only compared with each other: a timer's
      // value on a shared machine is not a test.)
      for (const CollisionStepStats* s : {&stats[i], &stats2[i]}) {
        EXPECT_LE(s->wait_seconds, s->broad_seconds);
        EXPECT_LE(s->broad_seconds, s->seconds);
      }
      // The task's parts are timed inside it, one after the other: each is within its time.
      // With one thread it runs inline and is not background time at all.
      const CollisionStepStats& s = stats2[i];
      const double parts = s.background_grid_seconds + s.background_cell_loop_seconds +
                           s.background_output_seconds + s.background_records_seconds;
      EXPECT_EQ(stats[i].background_seconds, 0.0);
      EXPECT_EQ(stats[i].background_grid_seconds + stats[i].background_cell_loop_seconds, 0.0);
      if (s.speculative == 1) {
        EXPECT_LE(parts, s.background_seconds) << "step " << i;
      }
      for (const CollisionStepStats* t : {&stats[i], &stats2[i]}) {
        EXPECT_LE(t->predict_seconds, t->broad_seconds) << "step " << i;
      }
    }
  }
}

TEST(SelfCollision, LargeCrushedSphereDoesNotDependOnThreads) {
  // Enough candidate pairs (over 20,000) and filter survivors (over 8192) that the step's
  // parallel compactions of test lists, filter survivors and hits span several blocks: no
  // pair may touch (brute force, box-culled first), and 1, 2 and 3 threads must give the same
  // positions bit for bit.
  std::vector<CollisionStepStats> stats;
  const std::vector<Positions> one = crush_sphere(1, 5, true, &stats, 3, true);
  std::int64_t most_pairs = 0, most_survivors = 0, contacts = 0;
  for (const CollisionStepStats& s : stats) {
    most_pairs = std::max(most_pairs, s.pairs_broad);
    most_survivors = std::max(most_survivors, s.pairs_filtered);
    contacts += s.contacts;
  }
  EXPECT_GT(most_pairs, 20000);      // several of the compaction blocks (8192)
  EXPECT_GT(most_survivors, 8192);   // the survivor and hit compactions too
  EXPECT_GT(contacts, 1000);
  for (int threads : {2, 3}) {
    const std::vector<Positions> other = crush_sphere(threads, 5, true, nullptr, 3, false);
    ASSERT_EQ(one.size(), other.size());
    for (std::size_t i = 0; i < one.size(); ++i)
      EXPECT_EQ(one[i], other[i]) << threads << " threads, step " << i;
  }
  // The same with the speculative broad phase, whose classification compacts the live pairs
  // and their stencils in blocks of 4096 pairs: no pair may touch either.
  std::vector<CollisionStepStats> spec_stats;
  crush_sphere(2, 5, true, &spec_stats, 3, true, true);
  int speculative = 0;
  for (const CollisionStepStats& s : spec_stats) {
    speculative += s.speculative;
    if (s.speculative == 1) {
      EXPECT_GT(s.pairs_broad, 3 * 4096);
    }
  }
  EXPECT_GT(speculative, 0);
}

/// A push chain for the zone of the rescans (CollisionOptions::narrow_rescans), delta 1e-3:
/// four parallel triangles A > B > C > D (each inside the one below it, seen from above), B, C,
/// D at rest at z = 0, -2.2 delta, -3.7 delta, and A, pinned, moving from 3 delta to 0.2 delta
/// above B. Round 0 pushes B away from A, down toward C; a later round finds B and C, then C
/// and D, within delta: vertices that no earlier push moved, outside the zone. Beside them,
/// `fillers` pairs of parallel triangles 1.5 delta apart that never move keep the zone a small
/// part of the live pairs, except the first: 0.5 delta apart at rest (near, so never pushed)
/// and passing through each other, which only the fail-safe, after the zone is built, can
/// stop. Returns the end positions after one resolve.
Positions push_chain(bool narrow_rescans, int fillers, CollisionStepStats& stats) {
  constexpr double delta = 1e-3;
  const int n_tri = 4 + 2 * fillers;
  Faces faces(n_tri, 3);
  Positions x0(3 * n_tri, 3);
  auto triangle = [&](int t, double cx, double size, double z) {
    faces.row(t) << 3 * t, 3 * t + 1, 3 * t + 2;
    x0.row(3 * t) << cx - size, -size, z;
    x0.row(3 * t + 1) << cx + size, -size, z;
    x0.row(3 * t + 2) << cx, size, z;
  };
  triangle(0, 0.0, 0.02, 3.0 * delta);  // A
  triangle(1, 0.0, 0.05, 0.0);          // B
  triangle(2, 0.0, 0.10, -2.2 * delta); // C
  triangle(3, 0.0, 0.20, -3.7 * delta); // D
  for (int k = 0; k < fillers; ++k) {
    triangle(4 + 2 * k, 1.0 + 0.5 * k, 0.05, 1.5 * delta);
    triangle(5 + 2 * k, 1.0 + 0.5 * k, 0.10, 0.0);
  }
  if (fillers > 0) x0.block(12, 2, 3, 1).setConstant(0.5 * delta);
  Positions x1 = x0;
  x1.topRows(3).col(2).array() = 0.2 * delta;
  if (fillers > 0) x1.block(12, 2, 3, 1).setConstant(-0.5 * delta);
  Eigen::VectorXd w = Eigen::VectorXd::Ones(x0.rows());
  w.head(3).setZero();  // A is pinned: round 0 moves only B
  CollisionOptions opt;
  opt.delta = delta;
  opt.narrow_rescans = narrow_rescans;
  SelfCollision sc(faces, x0, opt);
  sc.resolve(x0, x1, w, stats);
  return x1;
}

TEST(SelfCollision, NarrowRescansGiveTheFullPassesResults) {
  // The passes after a push visit only the zone around the step's moved vertices while no other
  // vertex moves, and must collect exactly what a pass over every live pair collects: the same
  // positions bit for bit. In the push chain, vertices outside the zone move after it is built
  // (C, then D): those passes must visit every pair again (with a zone pass instead, the pairs
  // of C and D would not be marked, and the result would differ).
  CollisionStepStats zone_stats, full_stats;
  const Positions zone = push_chain(true, 12, zone_stats);
  const Positions full = push_chain(false, 12, full_stats);
  EXPECT_EQ(zone, full);
  EXPECT_GE(zone_stats.contacts, 3);
  EXPECT_GE(zone_stats.rounds, 3);  // the pushes cascade down the chain
  EXPECT_GT(zone_stats.rescans_in_zone, 0);
  // The collection before round 0, the first pass after it (which builds the zone), and at
  // least one pass that a vertex outside the zone made full.
  EXPECT_GE(zone_stats.rescans_full, 3);
  EXPECT_EQ(full_stats.rescans_in_zone, 0);
  EXPECT_EQ(zone_stats.rescans_full + zone_stats.rescans_in_zone, full_stats.rescans_full);
  EXPECT_GT(zone_stats.failsafe_vertices, 0);  // the near pair, reverted
  EXPECT_EQ(zone_stats.failsafe_vertices, full_stats.failsafe_vertices);
  // Without the fillers the zone is most of the pairs: no zone pass, the same result.
  CollisionStepStats small_stats, small_full_stats;
  EXPECT_EQ(push_chain(true, 0, small_stats), push_chain(false, 0, small_full_stats));
  EXPECT_EQ(small_stats.rescans_in_zone, 0);
  EXPECT_GE(small_stats.contacts, 3);
}

}  // namespace
}  // namespace shellcontract
