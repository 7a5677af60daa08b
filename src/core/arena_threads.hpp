// The thread count of a TBB arena for a run's `threads` option.
#pragma once

#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <algorithm>

namespace shellcontract {

/// 0: TBB's automatic count (the machine's). A count above the machine's is held to the
/// machine's: TBB would run no more workers than that anyway, but asked for more it prints a
/// warning of its own ("TBB Warning: The number of workers is currently limited ...") that no
/// front end can keep quiet (-q). Raising TBB's limit instead (global_control) starts the extra
/// threads, and a worker that starts another cannot report a refused pthread_create as an error:
/// the process aborts when memory is short (tests/cli/test_cli_out_of_memory.cpp). The results do
/// not depend on the count.
inline int arena_threads(int requested) {
  if (requested <= 0) return tbb::task_arena::automatic;
  return std::min(requested, std::max(1, tbb::info::default_concurrency()));
}

}  // namespace shellcontract
