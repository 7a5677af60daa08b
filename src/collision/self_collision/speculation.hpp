// The speculative broad phase (part of the broad phase, CollisionOptions::speculative): predict()
// builds the predicted swept boxes and starts the grid over them on a spare thread while the
// constraint solve runs; complete() keeps the grid's pairs whose actual boxes overlap and
// queries the grid again for the vertices that escaped their predicted boxes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "collision/broad_phase.hpp"
#include "collision/self_collision/common.hpp"
#include "collision/self_collision/contact_cache.hpp"
#include "collision/self_collision/rest_pairs.hpp"
#include "collision/self_collision/step_pairs.hpp"
#include "shellcontract/observer.hpp"
#include "shellcontract/simulation_options.hpp"

namespace shellcontract::collision_pipeline {

/// Owns the prediction, its boxes and skins, the background task's flags and the completion's
/// buffers. The broad phase's candidates (`candidates`, whose grid the queries read) and the
/// step's pair records are given to each call: from predict() until complete() (or the next
/// predict(), or wait()) the background task writes them.
class Speculation {
 public:
  Speculation(const CollisionTopology& topo, const CollisionOptions& options, Workers& workers);

  /// SelfCollision::predict: the prediction (the guess plus the last step's correction, then
  /// `cache`'s warm start if CollisionOptions::warm_start), its boxes grown by the skins, and the
  /// background task: the grid over the boxes into `candidates` and the records with their
  /// rest-state roles into pairs.records. Nothing if the options ask for no speculation.
  void predict(const Positions& x0, const Positions& x_guess, const Eigen::VectorXd& w,
               const ContactCache& cache, const RestPairs& rest, CandidatePairs& candidates,
               StepPairs& pairs);

  /// Whether a prediction waits for complete().
  bool pending() const { return pending_; }

  /// Waits for the background task (or runs it here), then sets `pairs` (records, roles, flags,
  /// live pairs and round 0's tests) and `regions` as the plain broad phase would for (x0, x1),
  /// with the same candidate pairs. Returns false (nothing handed over) if the plain broad phase
  /// must run instead: x0 is not predict's, too many vertices left their predicted boxes, the
  /// task failed, or the positions are not usable.
  bool complete(const Positions& x0, const Positions& x1, const RestPairs& rest,
                CandidatePairs& candidates, StepPairs& pairs, Regions& regions,
                CollisionStepStats& stats);

  /// The solve's correction of the guess (x1 minus the guess), for the next prediction; called
  /// by every resolve with its solved end positions, before the warm start.
  void take_correction(const Positions& x1);

  /// predict's own wall time since the last call (then 0).
  double take_predict_seconds() {
    const double s = predict_seconds_;
    predict_seconds_ = 0.0;
    return s;
  }

  /// Waits for a background task still running, ignoring its failure (before destruction).
  void wait() noexcept;

  /// What the next prediction depends on (SelfCollision::PersistentState).
  const Positions& correction() const { return correction_; }
  const Eigen::VectorXd& skin() const { return skin_; }
  void restore(Positions correction, Eigen::VectorXd skin) {
    correction_ = std::move(correction);
    skin_ = std::move(skin);
  }

 private:
  /// The skin of a vertex's predicted box is SKIN_MIN delta plus SKIN_GROWTH times its
  /// prediction error (max norm) of the last step. The prediction error is small for most
  /// vertices, with a tail at the contacts, and the same vertices keep large errors from step to
  /// step; so a skin that grows with a vertex's last error leaves few vertices outside their
  /// boxes at a smaller mean skin than a fixed skin, whose grid would cost more (measured on
  /// bear; lab/history.md).
  static constexpr double SKIN_MIN = 1.5;
  static constexpr double SKIN_GROWTH = 4.0;
  /// If more than ESCAPE_LIMIT vertices, or this fraction of them if more, left their predicted
  /// boxes, the queries would approach a full broad phase: the plain one runs.
  static constexpr double ESCAPE_LIMIT = 64.0;
  static constexpr double ESCAPE_FRACTION = 1.0 / 32.0;
  /// Escaped primitives per task of the grid queries: a few per task, each query being costly
  /// next to a task's overhead.
  static constexpr std::size_t QUERY_BLOCK = 8;

  /// A pair the grid queries found, ready to append.
  struct QueryHit {
    PairRecord record;
    std::uint8_t role = NORMAL;  ///< its rest-state PairRole
    std::uint8_t stale = 0;      ///< to test (not flagged far, not excluded)
  };
  /// One block of the grid queries (buffers reused between calls).
  struct QueryBlock {
    std::vector<std::uint32_t> hits;  ///< query_kept_grid's output
    std::vector<QueryHit> pairs;      ///< the (escaped, grid) pairs to append, in query order
  };
  /// One block of the completion's pass over the vertices: its escaped vertices and whether its
  /// x0 differs from predict's.
  struct VertexBlock {
    std::size_t escaped = 0;
    bool other_x0 = false;
  };

  /// The background task: the grid over boxes_ and the records of its pairs.
  void run_task(const RestPairs& rest, CandidatePairs& candidates, StepPairs& pairs);
  /// complete()'s classification of the grid's pairs for the actual boxes: roles, flags, the
  /// live pairs and round 0's tests, in one pass; returns the pairs kept.
  std::size_t classify(StepPairs& pairs, std::size_t nvf, double far_gap);
  /// complete()'s queries for the primitives in escaped_prims_: their pairs, appended to `pairs`
  /// after the grid's (records, flags, live pairs, round 0's tests); returns how many.
  std::size_t query_escaped(const RestPairs& rest, const CandidatePairs& candidates,
                            StepPairs& pairs, double far_gap);

  const CollisionTopology& topo_;
  CollisionOptions options_;
  Workers& workers_;

  bool guess_set_ = false;              ///< predict ran since the last resolve (guess_ is its)
  bool pending_ = false;                ///< predict made a prediction resolve has not used yet
  bool enqueued_ = false;               ///< ... and enqueued its task (not with one thread)
  bool task_ok_ = false;                ///< the task built a grid (set by the task)
  double task_seconds_ = 0.0;           ///< the task's wall time (set by the task)
  double task_records_seconds_ = 0.0;   ///< the task's time filling the pair records
  double predict_seconds_ = 0.0;        ///< predict's own wall time, until resolve reports it
  Positions x0_;                        ///< x0 given to predict
  Positions guess_;                     ///< x_guess given to predict
  Positions pred_;                      ///< predicted end positions
  Positions correction_;                ///< last step: solved end positions minus the guess
  Eigen::VectorXd skin_;                ///< per vertex, for the next prediction
  std::vector<VertexBox> boxes_;        ///< predicted boxes, grown by the skin
  std::vector<VertexBox> exact_boxes_;  ///< actual boxes (complete)
  PairArray<std::uint8_t> base_role_;   ///< per speculative pair: its rest-state PairRole
  std::vector<std::uint8_t> escaped_;   ///< per vertex: actual box not inside the predicted one
  std::vector<std::uint32_t> escaped_prims_;  ///< their vertices, faces and edges (grid ids)
  std::vector<VertexBlock> vertex_blocks_;
  std::vector<std::uint8_t> block_finite_;  ///< predict: per block of vertices, all finite
  std::vector<QueryBlock> query_blocks_;
  std::vector<QueryHit> sweep_hits_;      ///< the escaped primitives' pairs among themselves
  std::vector<std::size_t> block_kept_;   ///< per block of the classification: pairs kept
  std::vector<std::size_t> block_live_;   ///< ... its live pairs (see StepPairs::collect_live)
  std::vector<std::size_t> block_tests_;  ///< ... its round-0 tests
  std::vector<std::pair<double, std::uint32_t>> sweep_order_;  ///< escaped primitives by x
};

}  // namespace shellcontract::collision_pipeline
