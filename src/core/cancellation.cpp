// The cancel request of a run in preparation (cancellation.hpp).
#include "core/cancellation.hpp"

#include <utility>

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

}  // namespace shellcontract
