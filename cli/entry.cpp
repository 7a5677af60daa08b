// The `shellcontract` tool's entry point (cli_main, called by cli/main.cpp's main): the process's
// signal and thread set-up, then the subcommand. It is a function, not main itself, so that a test
// program (tests/tools/held_cli.cpp) runs the very same code with a test hook set.
#include <fcntl.h>
#include <sys/resource.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "core/memory_error.hpp"
#include "core/usable_cpus.hpp"
#include "mesh/file_safety.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/version.hpp"

namespace {

constexpr const char* USAGE = R"(usage: shellcontract <command> [options]

commands:
  run INPUT -o OUTPUT [options]    contract a closed mesh (see 'shellcontract run --help')
  check INPUT [--json]             report whether a mesh can be used, and why not
  repair INPUT -o OUTPUT           make a refused mesh usable (fill holes, stitch, orient ...)
  regions INPUT [-o OUT.ply]       the spherical regions that --regions auto would choose
  reconstruct POINTS -o OUT        closed surface from an oriented point set (the kitten)
  bench ccd --queries DIR          CCD narrow phase against benchmark queries with ground truth
  bench error INPUT [options]      speed against error of the solver (table, CSV, gnuplot plot)
  sweep SWEEP.json -o DIR          many runs (meshes x options) on Dask distributed, resumable

  shellcontract <command> --help   options of one command
  shellcontract --version

exit codes: 0 success, 1 bad usage, 2 bad input (mesh, face list, weights, checkpoint),
            3 simulation failed (NaN or blow-up), out of memory or a resource the system refused
            (a thread, an open file), 4 new self-intersections found
            by validation, 5 target volume or stop ratio not reached, 130 interrupted (Ctrl-C,
            SIGTERM, SIGHUP, SIGUSR1)
)";

constexpr const char* BENCH_USAGE = R"(usage: shellcontract bench <ccd|error> [options]

  bench ccd --queries DIR          CCD narrow phase against benchmark queries with ground truth
  bench error INPUT [options]      speed against error of the solver (table, CSV, gnuplot plot)

  shellcontract bench ccd --help, shellcontract bench error --help: options of one benchmark
)";

constexpr std::size_t MAIN_STACK_BYTES = std::size_t{1} << 20;

/// Maps the main thread's first MiB of stack while there is room. That stack grows on demand, and
/// under an address-space limit (`ulimit -v`, how the out-of-memory tests run) a growth that
/// finds no room is a SIGSEGV, not a std::bad_alloc the commands report with exit code 3. Eigen
/// keeps temporaries of up to 128 KiB on the stack (EIGEN_STACK_ALLOCATION_LIMIT: the sparse LDLT
/// of the region finder's heat steps puts three vectors of the mesh's size there), so on a main
/// thread whose stack had never been that deep the first factorization could be the crash.
/// Pages once mapped stay mapped, so later frames within this depth need no new room.
[[gnu::noinline]] void map_main_stack() {
  volatile char frame[MAIN_STACK_BYTES];
  for (std::size_t i = 0; i < sizeof(frame); i += 4096) frame[i] = 0;
}

/// Why map_main_stack would find no room, or empty: mapping it under a limit that leaves less
/// than its MiB (an address-space limit nearly filled by the program and its libraries, or a
/// stack limit below it) is itself the SIGSEGV it is there to prevent. The margin covers the
/// frames below it and the stack already in use.
std::string main_stack_problem() {
  constexpr std::size_t MARGIN = std::size_t{256} << 10;
  rlimit stack{};
  if (::getrlimit(RLIMIT_STACK, &stack) == 0 && stack.rlim_cur != RLIM_INFINITY &&
      stack.rlim_cur < MAIN_STACK_BYTES + MARGIN)
    return "the stack limit (ulimit -s) is " + std::to_string(stack.rlim_cur >> 10) +
           " KiB; it needs at least " + std::to_string((MAIN_STACK_BYTES + MARGIN) >> 10) + " KiB";
  rlimit space{};
  if (::getrlimit(RLIMIT_AS, &space) != 0 || space.rlim_cur == RLIM_INFINITY) return {};
  // /proc/self/statm's first field: the pages the process has mapped, which the limit counts.
  const int fd = ::open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return {};
  char text[128] = {};
  const ssize_t n = ::read(fd, text, sizeof(text) - 1);
  ::close(fd);
  if (n <= 0) return {};
  const unsigned long long mapped =
      std::strtoull(text, nullptr, 10) * static_cast<unsigned long long>(::sysconf(_SC_PAGESIZE));
  if (mapped + MAIN_STACK_BYTES + MARGIN <= space.rlim_cur) return {};
  return "the address-space limit (ulimit -v) of " + std::to_string(space.rlim_cur >> 10) +
         " KiB leaves no room for the stack beside the program itself (" +
         std::to_string(mapped >> 10) + " KiB)";
}

/// The subcommand's exit code; 1 for an unknown one.
int dispatch(const std::string& command, int argc, char** argv) {
  // Subcommands see their own name as argv[0].
  if (command == "run") return shellcontract::cli::command_run(argc - 1, argv + 1);
  if (command == "check") return shellcontract::cli::command_check(argc - 1, argv + 1);
  if (command == "repair") return shellcontract::cli::command_repair(argc - 1, argv + 1);
  if (command == "regions") return shellcontract::cli::command_regions(argc - 1, argv + 1);
  if (command == "reconstruct") return shellcontract::cli::command_reconstruct(argc - 1, argv + 1);
  if (command == "sweep") return shellcontract::cli::command_sweep(argc - 1, argv + 1);
  if (command == "bench") {
    if (argc >= 3 && std::strcmp(argv[2], "ccd") == 0)
      return shellcontract::cli::command_bench_ccd(argc - 2, argv + 2);
    if (argc >= 3 && std::strcmp(argv[2], "error") == 0)
      return shellcontract::cli::command_bench_error(argc - 2, argv + 2);
    // 'shellcontract <command> --help' holds for bench too: its subcommands.
    if (argc >= 3 && (std::strcmp(argv[2], "--help") == 0 || std::strcmp(argv[2], "-h") == 0)) {
      std::cout << BENCH_USAGE;
      return 0;
    }
    std::cerr << "shellcontract bench: expected 'ccd' or 'error' (try 'shellcontract bench error --help')\n";
    return 1;
  }
  std::cerr << "shellcontract: unknown command '" << command << "'\n\n" << USAGE;
  return 1;
}

/// What a command printed on stdout is its product where it has no file (`check --json >
/// report.json`, `regions`, `repair --json`, `bench`): a write that failed (a full disk, a file
/// size limit, stdout closed) would otherwise end with exit 0 and an empty or cut report, which a
/// CI step takes for a pass. So stdout is flushed here, and a failure is bad usage's exit code 1
/// ("an output that cannot be written", docs/cli.md), or the command's own failing code.
int finish_stdout(const std::string& command, int code) {
  errno = 0;
  std::cout.flush();
  const bool written = std::cout.good() && std::fflush(stdout) == 0 && !std::ferror(stdout);
  if (written) return code;
  const int error = errno;
  std::cerr << "shellcontract " << command << ": cannot write to standard output"
            << (error != 0 ? std::string(": ") + std::strerror(error) : std::string())
            << " (what it printed is incomplete)\n";
  return code == 0 ? 1 : code;
}

}  // namespace

int shellcontract::cli::cli_main(int argc, char** argv) {
  // A closed pipe (stderr piped to `head`, a log filter that exited) and a file size limit
  // (`ulimit -f`, which batch systems pass on) would end the process by SIGPIPE or SIGXFSZ: the
  // run lost, its temporaries left. Ignored, the write fails instead: on stderr the messages stop
  // (the stream stays failed, the run goes on), on a file it is the "cannot write ...: File too
  // large" of a full disk (the old file kept, the other outputs written, exit 1). A command that
  // runs another program (sweep: Python) passes this on; Python ignores both itself anyway.
  std::signal(SIGPIPE, SIG_IGN);
  std::signal(SIGXFSZ, SIG_IGN);
  if (argc < 2) {
    std::cerr << USAGE;
    return 1;
  }
  std::string command = argv[1];
  // `shellcontract help run` (or --help run) is `shellcontract run --help`, `help bench ccd` is
  // `bench ccd --help`: the words after help name one command, and anything else is refused
  // rather than ignored.
  static char help_flag[] = "--help";
  std::vector<char*> help_argv;
  if (command == "--help" || command == "-h" || command == "help") {
    if (argc == 2) {
      std::cout << USAGE;
      return finish_stdout(command, 0);
    }
    const bool bench_pair = argc == 4 && std::strcmp(argv[2], "bench") == 0;
    if (argc > 3 && !bench_pair) {
      std::cerr << "shellcontract " << command << ": expected one command after it, got '"
                << argv[2] << "' and '" << argv[3] << "'\n(see 'shellcontract --help')\n";
      return 1;
    }
    help_argv.assign(argv, argv + argc);
    help_argv.erase(help_argv.begin() + 1);
    help_argv.push_back(help_flag);
    help_argv.push_back(nullptr);
    argc = static_cast<int>(help_argv.size()) - 1;
    argv = help_argv.data();
    command = argv[1];
    if (command == "--help" || command == "-h" || command == "help") {  // `help help`
      std::cout << USAGE;
      return finish_stdout(command, 0);
    }
  }
  if (command == "--version" && argc > 2) {
    std::cerr << "shellcontract --version: takes no argument, got '" << argv[2] << "'\n";
    return 1;
  }
  try {
    // A mistyped SHELLCONTRACT_KERNELS is refused before anything runs, not taken as "auto".
    if (command == "--version") {
      const std::string identity = shellcontract::tool_identity();
      std::cout << "shellcontract " << identity << '\n';
      return finish_stdout(command, 0);
    }
    shellcontract::kernel_class();
  } catch (const shellcontract::UsageError& e) {
    std::cerr << "shellcontract: " << e.what() << '\n';
    return 1;
  }
  if (const std::string problem = main_stack_problem(); !problem.empty()) {
    std::cerr << "shellcontract " << command << ": out of memory at start: " << problem
              << " (nothing was read or written)\n";
    return 3;
  }
  map_main_stack();
  // TBB's own thread count is the CPU affinity's, blind to a cgroup CPU quota: the work that runs
  // outside a run's arena (the planning's broad phase) took a thread per core of a 64-core host
  // in a container given 2 CPUs. Held to the CPUs this process may use, as the runs' arenas are
  // (core/arena_threads.hpp).
  if (shellcontract::usable_cpus() < tbb::info::default_concurrency()) {
    // Never destroyed: at its destruction TBB lifts the limit and starts a worker, at exit.
    static const auto* const limit =
        new tbb::global_control(tbb::global_control::max_allowed_parallelism,
                                static_cast<std::size_t>(shellcontract::usable_cpus()));
    static_cast<void>(limit);
  }
  // One ending for Ctrl-C, SIGTERM, SIGHUP and SIGUSR1 in every command, with or without
  // --checkpoint: the temporaries removed, exit code 130 (docs/cli.md). Installed now, not at the
  // first temporary, so that a signal before any file is written ends the same way. Where the
  // signal is ignored (a background job of a script, `nohup`), it stays ignored.
  shellcontract::set_interrupt_exit_status(130);
  shellcontract::install_interrupt_cleanup();
  try {
    return finish_stdout(command, dispatch(command, argc, argv));
  } catch (const shellcontract::OutOfMemoryError& e) {
    // An input larger than the memory there is (its reader's message names it): the same exit
    // code as memory running out anywhere else, not a bad input's 2.
    std::cerr << "shellcontract " << command << ": " << e.what()
              << " (outputs are written whole or not at all)\n";
    return 3;
  } catch (const std::bad_alloc&) {
    // A large enough mesh exhausts any machine; that must end with a message and an exit code,
    // not an abort. `run` says more itself (which frame, what it wrote).
    std::cerr << "shellcontract " << command
              << ": out of memory (outputs are written whole or not at all)\n";
    return 3;
  } catch (const std::runtime_error& e) {
    // The commands catch their own errors (bad usage, bad input); what is left is a resource
    // the system refused, such as a thread (TBB's "pthread_create has failed").
    std::cerr << "shellcontract " << command << ": " << e.what()
              << " (outputs are written whole or not at all)\n";
    return 3;
  }
}
