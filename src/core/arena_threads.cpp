// The process's task arenas, one per thread count (arena_threads.hpp).
#include "core/arena_threads.hpp"

#include <map>
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
  if (arena == nullptr) arena = new tbb::task_arena(threads);
  return *arena;
}

}  // namespace shellcontract
