// A run's cancel request during its preparation: the region selection and the Simulator's
// construction take long on a large mesh, and before, only the frame loop asked the observer.
// run_contraction opens a CancellationScope that asks the observer's cancelled() (and the
// checkpointer's stop()) on its own thread; the long steps call cancellation_point() between
// their stages, and run_contraction turns the throw into RunStatus::Cancelled.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <thread>

namespace shellcontract {

/// Thrown by cancellation_point; run_contraction catches it, nothing else should.
struct PreparationCancelled {};

/// While alive, cancellation_point() on the thread that made it asks `cancelled`. A nested
/// scope takes over until it ends.
class CancellationScope {
 public:
  explicit CancellationScope(std::function<bool()> cancelled);
  ~CancellationScope();
  CancellationScope(const CancellationScope&) = delete;
  CancellationScope& operator=(const CancellationScope&) = delete;

  /// This thread's scope, or null.
  static const CancellationScope* current();

  /// Makes `scope` (may be null) this thread's while alive: a task that runs part of the
  /// preparation on another thread (the part finder's two finders side by side) stops too once
  /// the run's own thread has seen the cancel. It never asks itself: the observer is asked on
  /// the run's thread only (shellcontract/observer.hpp).
  class Join {
   public:
    explicit Join(const CancellationScope* scope);
    ~Join();
    Join(const Join&) = delete;
    Join& operator=(const Join&) = delete;

   private:
    const CancellationScope* previous_;
  };

 private:
  std::function<bool()> cancelled_;
  std::thread::id owner_;
  mutable std::atomic<bool> seen_{false};
  const CancellationScope* previous_;
  friend void cancellation_point();
};

/// Throws PreparationCancelled when this thread's scope says the run is cancelled; does nothing
/// without one (a finder or a Simulator used on its own, a worker thread). Called between stages;
/// inside a parallel loop's body only under a Join (the exception then leaves the loop).
void cancellation_point();

/// Elements (faces, vertices, pairs) of a long serial loop of the preparation between two
/// cancellation points: a large mesh's single calls (curvature, the finder's arrays, the rest
/// gaps) hear a cancel within a small share of their time, and the question costs nothing beside
/// that much work.
inline constexpr std::size_t CANCELLATION_CHUNK = std::size_t{1} << 14;

/// How often a thread that waits for another's part of the preparation asks its scope.
inline constexpr std::chrono::milliseconds CANCELLATION_WAIT_POLL{20};

/// Runs `here` on this thread and `beside` on a TBB worker at the same time (on this thread
/// after `here` when no worker took it), `beside` under a Join of this thread's scope, and
/// returns once both have ended. While this thread waits for `beside` it keeps asking its scope
/// (every CANCELLATION_WAIT_POLL): the worker's cancellation points only see a cancel that the
/// run's thread has seen, and with tbb::parallel_invoke a run's thread that had finished its half
/// asked nothing until the other half ended (the part finder's two finders).
/// Rethrows `here`'s exception (or the cancel heard while waiting) before `beside`'s.
void run_side_by_side(const std::function<void()>& here, const std::function<void()>& beside);

}  // namespace shellcontract
