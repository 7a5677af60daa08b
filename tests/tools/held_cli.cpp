// The `shellcontract` tool (cli_main, the same code) with a test hook set: each temporary file the
// library creates is held open, created and not yet registered for removal, for HOLD_MS
// milliseconds, after the line "shellcontract test: temporary created" on stderr. A test waits
// for the n-th line and signals the process there (tests/cli/test_cli_interrupt.cpp,
// test_cli_signals.cpp): the window a signal used to find.
//   held_cli HOLD_MS COMMAND [options]   as `shellcontract COMMAND [options]`
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <ctime>

#include "cli/commands.hpp"
#include "mesh/file_safety.hpp"

namespace {

long hold_ms = 0;

void hold() {
  static constexpr char line[] = "shellcontract test: temporary created\n";
  (void)!::write(2, line, sizeof line - 1);
  const struct timespec ts = {hold_ms / 1000, (hold_ms % 1000) * 1000000L};
  ::nanosleep(&ts, nullptr);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || (hold_ms = std::atol(argv[1])) <= 0) {
    std::fprintf(stderr, "usage: held_cli HOLD_MS COMMAND [options]\n");
    return 1;
  }
  shellcontract::set_temporary_created_hook(hold);
  argv[1] = argv[0];  // the tool sees `held_cli COMMAND [options]`
  return shellcontract::cli::cli_main(argc - 1, argv + 1);
}
