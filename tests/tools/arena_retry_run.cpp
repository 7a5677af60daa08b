// A run after the run's task arena could not be made for want of memory, in a process of its own
// (tests/sim/test_shared_arena.cpp): the address space (RLIMIT_AS) held to what the process has
// plus HEADROOM_KIB while an arena of two threads (ArenaLease) is made and entered, then the limit
// lifted and a run on two threads, as a Python session retries after a MemoryError. A process of
// its own because the arena must be the process's first (a test binary has made its arenas before).
// Usage: arena_retry_run MESH HEADROOM_KIB
// Prints to stderr "arena: made" or "arena: refused (WHAT)", then "run: STATUS"; exit 1 on an
// error outside the arena.
#include <sys/resource.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <new>
#include <string>

#include "core/arena_threads.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"

namespace {

/// The process's address space in bytes (Linux), -1 if unknown.
long long address_space() {
  std::ifstream status("/proc/self/status");
  std::string key;
  long long kib = -1;
  while (status >> key) {
    if (key == "VmSize:") {
      status >> kib;
      break;
    }
    status.ignore(1 << 20, '\n');
  }
  return kib < 0 ? -1 : kib * 1024;
}

bool limit_address_space(rlim_t bytes) {
  const struct rlimit lim { bytes, RLIM_INFINITY };
  return ::setrlimit(RLIMIT_AS, &lim) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace shellcontract;
  if (argc != 3) {
    std::fprintf(stderr, "usage: arena_retry_run MESH HEADROOM_KIB\n");
    return 1;
  }
  try {
    const Mesh mesh = read_input_mesh(argv[1]);
    RunOptions options;
    set_run_option(options, "frames", "2");
    set_run_option(options, "threads", "2");
    const long long now = address_space();
    if (now < 0 || !limit_address_space(static_cast<rlim_t>(now + std::atoll(argv[2]) * 1024))) {
      std::fprintf(stderr, "arena_retry_run: cannot limit the address space\n");
      return 1;
    }
    std::exception_ptr refused;  // kept as it is: a message made under the limit could fail too
    try {
      ArenaLease(2).arena().execute([] {});
    } catch (...) {
      refused = std::current_exception();
    }
    limit_address_space(RLIM_INFINITY);
    if (!refused) std::fprintf(stderr, "arena: made\n");
    try {
      if (refused) std::rethrow_exception(refused);
    } catch (const std::exception& e) {  // std::bad_alloc, or a thread the system refused
      std::fprintf(stderr, "arena: refused (%s)\n", e.what());
    }
    const RunResult r = run_contraction(mesh, options);
    std::fprintf(stderr, "run: %s\n", status_name(r.status));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "arena_retry_run: %s\n", e.what());
    return 1;
  }
  return 0;
}
