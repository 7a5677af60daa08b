// A run's cancel request during its preparation: the region selection and the Simulator's
// construction take long on a large mesh, and before, only the frame loop asked the observer.
// run_contraction opens a CancellationScope that asks the observer's cancelled() (and the
// checkpointer's stop()) on its own thread; the long steps call cancellation_point() between
// their stages, and run_contraction turns the throw into RunStatus::Cancelled.
#pragma once

#include <atomic>
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

}  // namespace shellcontract
