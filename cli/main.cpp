// shellcontract: contract a closed triangle mesh like a thin elastic shell under outside air
// pressure (Sun et al., J. Software 2020). The tool is cli_main (cli/entry.cpp), which dispatches
// to the subcommands.
#include "commands.hpp"

int main(int argc, char** argv) { return shellcontract::cli::cli_main(argc, argv); }
