// The `shellcontract` tool (cli_main, the same code) with the cap finder's stage hook set: the
// line "shellcontract test: region stage STAGE" on stderr as each stage of the finder ends. A
// test waits for a stage's line and signals the process there
// (tests/cli/test_cli_interrupt_selection.cpp): no sleep decides when.
//   staged_cli COMMAND [options]   as `shellcontract COMMAND [options]`
#include <unistd.h>

#include <cstring>
#include <string>

#include "cli/commands.hpp"
#include "geometry/region_stage_hook.hpp"

namespace {

void print_stage(const char* stage) {
  const std::string line = std::string("shellcontract test: region stage ") + stage + "\n";
  (void)!::write(2, line.data(), line.size());
}

}  // namespace

int main(int argc, char** argv) {
  shellcontract::detail::set_region_stage_hook(print_stage);
  return shellcontract::cli::cli_main(argc, argv);
}
