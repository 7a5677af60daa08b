// The process's pool of task arenas, leased one run at a time (arena_threads.hpp).
#include "core/arena_threads.hpp"

#include <pthread.h>

#include <atomic>
#include <map>
#include <mutex>
#include <vector>

namespace shellcontract {

namespace {

struct Pool {
  std::mutex lock;
  std::map<int, std::vector<tbb::task_arena*>> free;  ///< by thread count
  std::map<int, std::size_t> made;                    ///< by thread count
};

// Never destroyed: an arena destroyed at exit would outlive TBB's own teardown in a module
// unloaded late (Python), and the pool is bounded by the most runs at once.
Pool* the_pool = nullptr;

std::atomic<ArenaMadeHook> arena_made_hook{nullptr};

Pool& pool() {
  static Pool* p = [] {
    the_pool = new Pool();
    // A fork while another thread holds the mutex (making an arena) left it held in the child,
    // where no thread would release it: the child's first lease waited for ever. The fork waits
    // for the mutex instead, and parent and child release it.
    pthread_atfork([] { the_pool->lock.lock(); }, [] { the_pool->lock.unlock(); },
                   [] { the_pool->lock.unlock(); });
    return the_pool;
  }();
  return *p;
}

void give_back(int threads, tbb::task_arena* arena) {
  Pool& p = pool();
  std::lock_guard<std::mutex> guard(p.lock);
  // The vector's room was reserved when the arena was made, so this does not throw.
  p.free[threads].push_back(arena);
}

/// The run of this thread whose parts are being made (RunArenaScope).
thread_local const ArenaLease* current_run = nullptr;

}  // namespace

ArenaLease::ArenaLease(int requested) : threads_(arena_threads(requested)) {
  const int threads = threads_;
  Pool& p = pool();
  tbb::task_arena* arena = nullptr;
  {
    std::lock_guard<std::mutex> guard(p.lock);
    std::vector<tbb::task_arena*>& free = p.free[threads];
    if (!free.empty()) {
      arena = free.back();
      free.pop_back();
    } else {
      // Initialized here, and kept only once that succeeded. Left to its first execute, an arena
      // whose initialization threw (std::bad_alloc when memory runs out) stays "pending" in TBB's
      // once-state for ever, and every later run of that thread count in the process (a Python
      // session's retry after its MemoryError) spun waiting for it. One that failed is dropped
      // (never initialized, its destructor releases nothing of TBB's), so the next lease tries
      // again. Room for every arena of the count in the free list, so that giving one back
      // cannot fail.
      free.reserve(p.made[threads] + 1);
      auto made = std::make_unique<tbb::task_arena>(threads);
      made->initialize();
      arena = made.release();
      ++p.made[threads];
      if (const ArenaMadeHook hook = arena_made_hook.load()) hook();
    }
  }
  // shared_ptr gives the arena back through the deleter if its own allocation throws.
  arena_ = std::shared_ptr<tbb::task_arena>(
      arena, [threads](tbb::task_arena* a) { give_back(threads, a); });
}

ArenaLease run_arena(int requested) {
  if (current_run != nullptr && current_run->threads() == arena_threads(requested))
    return *current_run;
  return ArenaLease(requested);
}

RunArenaScope::RunArenaScope(const ArenaLease& lease) : outer_(current_run) {
  current_run = &lease;
}

RunArenaScope::~RunArenaScope() { current_run = outer_; }

void set_arena_made_hook(ArenaMadeHook hook) { arena_made_hook.store(hook); }

std::size_t arenas_made(int requested) {
  Pool& p = pool();
  std::lock_guard<std::mutex> guard(p.lock);
  const auto it = p.made.find(arena_threads(requested));
  return it == p.made.end() ? 0 : it->second;
}

}  // namespace shellcontract
