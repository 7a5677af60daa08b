// The process's task arenas, one per thread count (arena_threads.hpp).
#include "core/arena_threads.hpp"

#include <map>
#include <memory>
#include <mutex>

namespace shellcontract {

tbb::task_arena& shared_arena(int requested) {
  static std::mutex lock;
  // Never destroyed: an arena destroyed at exit would outlive TBB's own teardown in a module
  // unloaded late (Python), and the set is bounded by the machine's thread counts.
  static auto* arenas = new std::map<int, tbb::task_arena*>();
  const int threads = arena_threads(requested);
  std::lock_guard<std::mutex> guard(lock);
  tbb::task_arena*& arena = (*arenas)[threads];
  if (arena == nullptr) {
    // Initialized here, and kept only once that succeeded. Left to its first execute, an arena
    // whose initialization threw (std::bad_alloc when memory runs out) stays "pending" in TBB's
    // once-state for ever, and every later run of that thread count in the process (a Python
    // session's retry after its MemoryError) spun waiting for it. One that failed is dropped
    // (never initialized, its destructor releases nothing of TBB's), so the next run tries again.
    auto made = std::make_unique<tbb::task_arena>(threads);
    made->initialize();
    arena = made.release();
  }
  return *arena;
}

}  // namespace shellcontract
