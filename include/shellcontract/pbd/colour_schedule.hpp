// Runs the colours of a Coloured Gauss-Seidel solve (math-spec 9.4) on several threads with one
// light barrier per colour instead of one tbb::parallel_for per colour: the threads enter once
// per solve and walk the same list of phases (every colour of every constraint kind, sweep after
// sweep). A phase is cut into chunks; thread t owns a contiguous block of them.
//
// Why this layout: on a VM whose two cores exchange a cache line in ~200 ns (the machine of
// 2026-11-24 measured a 430 ns round trip), a colour of bear takes only ~5-12 us on one thread,
// so a schedule that moves a shared line per chunk (one claim counter and one completion counter
// for all threads) spends as much on those transfers as on the work. Here a thread claims its own
// chunks in lines that only it writes, counts them locally, and publishes one completion count
// per phase in another line only it writes; the waiting thread reads that line. In the normal
// case a phase costs one line transfer per thread, plus the vertex rows the two halves share.
//
// Determinism: a phase's items (constraints of one colour) share no vertex, so which thread runs
// which chunk, and how the phase is cut, cannot change a bit of the result.
// Progress: a thread that has waited STEAL_AFTER_SPINS spins for a phase, or that sees another
// thread has not entered this run yet, claims the other threads' unclaimed chunks of it (from the
// back of their blocks), so the schedule completes whenever the helpers start, and a thread whose
// core the OS took away holds the others up for only that long.
// Threads: the caller plus the schedule's own SpinTeam (core/spin_team.hpp says why not TBB tasks).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <thread>
#include <vector>

#include "shellcontract/core/spin_team.hpp"

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
  /// @param spin_us  how long the helper threads poll for the next run before they block
  ColourSchedule(std::vector<ColourPhase> phases, int sweeps, int threads,
                 int spin_us = SpinTeam::DEFAULT_SPIN_US)
      : phases_(std::move(phases)), sweeps_(std::max(sweeps, 0)), threads_(std::max(threads, 1)) {
    chunk_.resize(phases_.size());
    chunks_.resize(phases_.size());
    for (std::size_t p = 0; p < phases_.size(); ++p) {
      const std::size_t n = phases_[p].end - phases_[p].begin;
      const std::size_t target = static_cast<std::size_t>(CHUNKS_PER_THREAD) * threads_;
      chunk_[p] = std::max<std::size_t>({phases_[p].grain, (n + target - 1) / target, 1});
      // At most CHUNKS_PER_THREAD * threads_ chunks, so a block has at most CLAIMS_PER_LINE.
      chunks_[p] = static_cast<int>((n + chunk_[p] - 1) / chunk_[p]);
    }
    lines_ = std::make_unique<Line[]>(line_count());
    arrived_ = std::make_unique<Line[]>(static_cast<std::size_t>(threads_));
    if (threads_ > 1) team_ = std::make_unique<SpinTeam>(threads_, spin_us);
  }

  /// Runs body(kind, begin, end) over every chunk of every phase, phase after phase, on the
  /// calling thread plus the threads - 1 helpers of the schedule's own SpinTeam. Not reentrant.
  template <class Body>
  void run(const Body& body) {
    // A new epoch instead of clearing every flag: a claim or count of an older run is simply
    // not of this epoch (and clearing would pull every line to this core once per run).
    const std::uint64_t epoch = ++epoch_;
    if (threads_ == 1) {
      walk(0, epoch, body);
      return;
    }
    // SpinTeam::run publishes epoch to the helpers and returns after all of them.
    team_->run([&](int t) { walk(t, epoch, body); });
  }

  int threads() const { return threads_; }

  /// Chunks per thread and phase: a few, so that work can be taken over from a thread slowed
  /// down by another process without moving a whole block.
  static constexpr int CHUNKS_PER_THREAD = 4;

 private:
  static constexpr int CLAIMS_PER_LINE = 8;
  static_assert(CHUNKS_PER_THREAD <= CLAIMS_PER_LINE, "a thread's block must fit one line");

  /// One cache line of one thread in one phase of one sweep: the claims of the thread's own
  /// chunks (the epoch that claimed each), then, in the next line, its completion count.
  struct alignas(64) Line {
    std::atomic<std::uint64_t> word[CLAIMS_PER_LINE];
  };

  /// (sweep, phase, thread) -> its claim line; its done line follows it.
  std::size_t claim_line(int s, std::size_t p, int t) const {
    return ((static_cast<std::size_t>(s) * phases_.size() + p) * static_cast<std::size_t>(threads_) +
            static_cast<std::size_t>(t)) * 2;
  }
  std::size_t line_count() const {
    return static_cast<std::size_t>(sweeps_) * phases_.size() * static_cast<std::size_t>(threads_) * 2;
  }

  /// Chunks [block_begin(p, t), block_begin(p, t + 1)) of phase p belong to thread t.
  int block_begin(std::size_t p, int t) const { return chunks_[p] * t / threads_; }

  /// Done counts are published as epoch * DONE_SCALE + count (count < DONE_SCALE).
  static constexpr std::uint64_t DONE_SCALE = std::uint64_t{1} << 20;

  template <class Body>
  void walk(int t, std::uint64_t epoch, const Body& body) {
    arrived_[static_cast<std::size_t>(t)].word[0].store(epoch, std::memory_order_relaxed);
    for (int s = 0; s < sweeps_; ++s)
      for (std::size_t p = 0; p < phases_.size(); ++p) {
        const ColourPhase& phase = phases_[p];
        std::uint64_t done = 0;  // chunks of this phase this thread ran
        // Chunk k of owner o: claimed by whoever swaps in the epoch first.
        auto try_run = [&](int o, int k) {
          std::atomic<std::uint64_t>& claim =
              lines_[claim_line(s, p, o)].word[k - block_begin(p, o)];
          if (claim.load(std::memory_order_relaxed) == epoch ||
              claim.exchange(epoch, std::memory_order_relaxed) == epoch)
            return;
          const std::size_t begin = phase.begin + static_cast<std::size_t>(k) * chunk_[p];
          body(phase.kind, begin, std::min(begin + chunk_[p], phase.end));
          ++done;
        };
        std::atomic<std::uint64_t>& published = lines_[claim_line(s, p, t) + 1].word[0];
        for (int k = block_begin(p, t); k < block_begin(p, t + 1); ++k) try_run(t, k);
        // Release: whoever reads this count sees the writes of the chunks it counts.
        published.store(epoch * DONE_SCALE + done, std::memory_order_release);
        // Wait until every chunk of the phase is done; after a while take the others' chunks.
        for (int spins = 0;; ++spins) {
          std::uint64_t total = 0;
          for (int o = 0; o < threads_; ++o) {
            const std::uint64_t v =
                lines_[claim_line(s, p, o) + 1].word[0].load(std::memory_order_acquire);
            if (v / DONE_SCALE == epoch) total += v % DONE_SCALE;
          }
          if (total == static_cast<std::uint64_t>(chunks_[p])) break;
          // A thread that has not started this run yet (a helper waking up) is not waited for.
          const std::uint64_t before = done;
          for (int o = 0; o < threads_; ++o)
            if (o != t && (spins >= STEAL_AFTER_SPINS ||
                           arrived_[static_cast<std::size_t>(o)].word[0].load(
                               std::memory_order_relaxed) != epoch))
              for (int k = block_begin(p, o + 1) - 1; k >= block_begin(p, o); --k) try_run(o, k);
          if (done != before) published.store(epoch * DONE_SCALE + done, std::memory_order_release);
          if (spins < SPINS_BEFORE_YIELD) {
#if defined(__x86_64__) || defined(__i386__)
            __builtin_ia32_pause();
#endif
          } else {
            std::this_thread::yield();
          }
        }
      }
  }

  /// Spins of a waiting thread before it takes over unclaimed chunks of the others (5-15 us of
  /// pause instructions, 68 ns each on the Zen 5 VM: more than a chunk normally takes).
  static constexpr int STEAL_AFTER_SPINS = 200;
  /// Spins before the waiting thread starts giving its core away between polls.
  static constexpr int SPINS_BEFORE_YIELD = 2000;

  std::vector<ColourPhase> phases_;
  std::vector<std::size_t> chunk_;  ///< items per chunk, per phase
  std::vector<int> chunks_;         ///< chunks per phase
  int sweeps_ = 0;
  int threads_ = 1;
  std::uint64_t epoch_ = 0;         ///< runs so far; the current run's claims carry it
  std::unique_ptr<Line[]> lines_;   ///< per (sweep, phase, thread): claim line, done line
  std::unique_ptr<Line[]> arrived_; ///< per thread: the epoch of the last run it entered
  std::unique_ptr<SpinTeam> team_;  ///< threads_ > 1 only
};

}  // namespace shellcontract
