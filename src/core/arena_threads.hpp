// The thread count of a TBB arena for a run's `threads` option, and the arena of that count.
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

/// The process's arena of arena_threads(requested) threads, made at its first use and kept: a run
/// (its solver, its collision step, its step's own work) works in it instead of arenas of its
/// own. TBB (oneTBB 2021.8) keeps some kilobytes of every arena that ran parallel work after the
/// arena is destroyed, so a program that calls the library thousands of times (a Python loop)
/// grew without bound (tests/sim/test_shared_arena.cpp). Runs on several threads at once may share
/// one: an arena takes work from several threads, and neither the results nor the colour
/// schedule's progress depend on which thread runs which task (colour_schedule.hpp).
tbb::task_arena& shared_arena(int requested);

}  // namespace shellcontract
