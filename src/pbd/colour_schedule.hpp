// Runs the colours of a Coloured Gauss-Seidel solve (math-spec 9.4) on several threads with one
// light barrier per colour instead of one tbb::parallel_for per colour: the threads enter once
// per solve and walk the same list of phases (every colour of every constraint kind, sweep after
// sweep). A phase is cut into chunks that threads claim from an atomic counter; a thread that
// finds no chunk left waits until every chunk of the phase is done, then moves on.
//
// Determinism: a phase's items (constraints of one colour) share no vertex, so which thread runs
// which chunk, and how the phase is cut, cannot change a bit of the result.
// Progress: a thread only ever waits for chunks that another thread has claimed and is running,
// so the schedule completes even if TBB runs the tasks one after the other on one thread.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <memory>
#include <thread>
#include <vector>

#include <tbb/task_arena.h>
#include <tbb/task_group.h>

namespace shellcontract {

/// One colour of one constraint kind: items [begin, end) of that kind.
struct ColourPhase {
  int kind = 0;           ///< caller's tag, passed back to the body
  std::size_t begin = 0;  ///< first item
  std::size_t end = 0;    ///< one past the last item
  std::size_t grain = 1;  ///< smallest chunk worth a claim (>= 1)
};

/// Phases of one sweep, repeated `sweeps` times per run. Allocates at construction only.
class ColourSchedule {
 public:
  ColourSchedule() = default;

  /// @param phases   one sweep's phases, in order
  /// @param sweeps   sweeps per run (>= 0)
  /// @param threads  threads that will run it (>= 1); sets the chunk sizes, about
  ///                 CHUNKS_PER_THREAD chunks per thread and phase (never below a phase's grain)
  ColourSchedule(std::vector<ColourPhase> phases, int sweeps, int threads)
      : phases_(std::move(phases)), sweeps_(std::max(sweeps, 0)), threads_(std::max(threads, 1)) {
    chunk_.resize(phases_.size());
    chunks_.resize(phases_.size());
    for (std::size_t p = 0; p < phases_.size(); ++p) {
      const std::size_t n = phases_[p].end - phases_[p].begin;
      const std::size_t target = static_cast<std::size_t>(CHUNKS_PER_THREAD) * threads_;
      chunk_[p] = std::max<std::size_t>({phases_[p].grain, (n + target - 1) / target, 1});
      chunks_[p] = static_cast<int>((n + chunk_[p] - 1) / chunk_[p]);
    }
    counters_ = std::make_unique<Counter[]>(phases_.size() * static_cast<std::size_t>(sweeps_));
    first_claim_.resize(phases_.size());
    for (std::size_t p = 0; p < phases_.size(); ++p) {
      first_claim_[p] = claims_per_sweep_;
      claims_per_sweep_ += static_cast<std::size_t>(chunks_[p]);
    }
    claims_ = std::make_unique<std::atomic<int>[]>(claims_per_sweep_ * static_cast<std::size_t>(sweeps_));
  }

  /// Runs body(kind, begin, end) over every chunk of every phase, phase after phase, on the
  /// calling thread plus threads - 1 tasks of the current arena. Call inside the arena that
  /// should run it (task_arena::execute). Not reentrant.
  template <class Body>
  void run(const Body& body) {
    const std::size_t total = phases_.size() * static_cast<std::size_t>(sweeps_);
    for (std::size_t i = 0; i < total; ++i) counters_[i].done.store(0, std::memory_order_relaxed);
    for (std::size_t i = 0; i < claims_per_sweep_ * static_cast<std::size_t>(sweeps_); ++i)
      claims_[i].store(0, std::memory_order_relaxed);
    if (threads_ == 1) {
      walk(0, body);
      return;
    }
    // Spawning publishes the reset counters to the tasks (task_group::run synchronizes).
    tbb::task_group group;
    for (int t = 1; t < threads_; ++t) group.run([&, t] { walk(t, body); });
    walk(0, body);
    group.wait();
  }

  int threads() const { return threads_; }

  /// Chunks per thread and phase: a few, so a thread slowed down by another process does not
  /// hold the whole phase back, and few enough that claims (one atomic add) stay rare.
  static constexpr int CHUNKS_PER_THREAD = 4;

 private:
  /// Completion counter of one phase of one sweep, on its own cache line.
  struct alignas(64) Counter {
    std::atomic<int> done{0};
  };

  /// Thread `t` first runs its own chunks (block t of the phase: the same part of the mesh in
  /// every colour, so its vertices stay in this core's cache), then helps with the others'
  /// unclaimed chunks from the back.
  template <class Body>
  void walk(int t, const Body& body) {
    for (int s = 0; s < sweeps_; ++s)
      for (std::size_t p = 0; p < phases_.size(); ++p) {
        const std::size_t id = static_cast<std::size_t>(s) * phases_.size() + p;
        std::atomic<int>* claimed = &claims_[first_claim_[p] + static_cast<std::size_t>(s) * claims_per_sweep_];
        const ColourPhase& phase = phases_[p];
        const int chunks = chunks_[p];
        const int own_begin = chunks * t / threads_, own_end = chunks * (t + 1) / threads_;
        auto run_chunk = [&](int k) {
          if (claimed[k].exchange(1, std::memory_order_relaxed) != 0) return;
          const std::size_t begin = phase.begin + static_cast<std::size_t>(k) * chunk_[p];
          body(phase.kind, begin, std::min(begin + chunk_[p], phase.end));
          // Release: the next phase's readers see this chunk's writes (acquire in wait_for).
          counters_[id].done.fetch_add(1, std::memory_order_release);
        };
        for (int k = own_begin; k < own_end; ++k) run_chunk(k);
        for (int k = chunks - 1; k >= own_end; --k) run_chunk(k);
        for (int k = own_begin - 1; k >= 0; --k) run_chunk(k);
        wait_for(counters_[id].done, chunks);
      }
  }

  /// Spins (briefly) then yields until counter reaches target: the other thread is running a
  /// chunk of a few microseconds, unless the OS took its core away.
  static void wait_for(const std::atomic<int>& counter, int target) {
    for (int spins = 0; counter.load(std::memory_order_acquire) < target; ++spins) {
      if (spins < SPINS_BEFORE_YIELD) {
#if defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#endif
      } else {
        std::this_thread::yield();
      }
    }
  }

  /// Pause instructions before the waiting thread gives its core away: a colour's usual wait
  /// for its last chunk is shorter, a stall longer (lab/history.md, "SPINS_BEFORE_YIELD").
  static constexpr int SPINS_BEFORE_YIELD = 2000;

  std::vector<ColourPhase> phases_;
  std::vector<std::size_t> chunk_;  ///< items per chunk, per phase
  std::vector<int> chunks_;         ///< chunks per phase
  int sweeps_ = 0;
  int threads_ = 1;
  std::unique_ptr<Counter[]> counters_;  ///< sweeps x phases
  std::vector<std::size_t> first_claim_;  ///< phase p's chunk flags start here within a sweep
  std::size_t claims_per_sweep_ = 0;
  std::unique_ptr<std::atomic<int>[]> claims_;  ///< 1 once a chunk is taken; sweeps x chunks
};

}  // namespace shellcontract
