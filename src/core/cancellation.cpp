// The cancel request of a run in preparation (cancellation.hpp).
#include "core/cancellation.hpp"

#include <condition_variable>
#include <exception>
#include <mutex>
#include <utility>

#include <tbb/task_group.h>

namespace shellcontract {
namespace {

/// Per thread: two runs on two threads (Python's contract() in a thread pool) ask their own.
thread_local const CancellationScope* current_scope = nullptr;

}  // namespace

CancellationScope::CancellationScope(std::function<bool()> cancelled)
    : cancelled_(std::move(cancelled)),
      owner_(std::this_thread::get_id()),
      previous_(current_scope) {
  current_scope = this;
}

CancellationScope::~CancellationScope() { current_scope = previous_; }

const CancellationScope* CancellationScope::current() { return current_scope; }

CancellationScope::Join::Join(const CancellationScope* scope) : previous_(current_scope) {
  current_scope = scope;
}

CancellationScope::Join::~Join() { current_scope = previous_; }

void cancellation_point() {
  const CancellationScope* s = current_scope;
  if (!s) return;
  if (s->seen_.load(std::memory_order_relaxed)) throw PreparationCancelled{};
  if (s->owner_ == std::this_thread::get_id() && s->cancelled_ && s->cancelled_()) {
    s->seen_.store(true, std::memory_order_relaxed);
    throw PreparationCancelled{};
  }
}

void run_side_by_side(const std::function<void()>& here, const std::function<void()>& beside) {
  const CancellationScope* const run = current_scope;
  // Whoever claims `beside` first runs it: a worker, or this thread once `here` has ended (with
  // one thread, or all of them busy, no worker may ever take the task).
  std::atomic<bool> claimed{false};
  std::mutex m;
  std::condition_variable ended;
  bool beside_ended = false;
  std::exception_ptr here_error, beside_error;
  tbb::task_group group;
  group.run([&] {
    if (claimed.exchange(true)) return;
    try {
      const CancellationScope::Join join(run);
      beside();
    } catch (...) {
      beside_error = std::current_exception();
    }
    {
      const std::lock_guard<std::mutex> lock(m);
      beside_ended = true;
    }
    ended.notify_all();
  });
  try {
    here();
  } catch (...) {
    here_error = std::current_exception();
  }
  if (!claimed.exchange(true)) {
    // Not started anywhere: this thread runs it, asking the scope itself (after a failure of
    // `here` there is nothing to run it for).
    if (!here_error) {
      try {
        beside();
      } catch (...) {
        beside_error = std::current_exception();
      }
    }
  } else {
    std::unique_lock<std::mutex> lock(m);
    while (!beside_ended) {
      ended.wait_for(lock, CANCELLATION_WAIT_POLL);
      if (beside_ended || here_error || !run) continue;
      lock.unlock();
      try {
        cancellation_point();  // once seen, the worker's next point throws too
      } catch (...) {
        here_error = std::current_exception();
      }
      lock.lock();
    }
  }
  group.wait();  // the task's frame, and a task never claimed
  if (here_error) std::rethrow_exception(here_error);
  if (beside_error) std::rethrow_exception(beside_error);
}

}  // namespace shellcontract
