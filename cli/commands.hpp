// The subcommands of the `shellcontract` tool. Each parses its own options and returns the
// process exit code (README.md, "Exit codes"). cli/ holds no physics and no geometry.
#pragma once

namespace shellcontract::cli {

/// The whole tool (`shellcontract COMMAND ...`): what main does, with main's arguments; returns
/// the process exit code. Sets the process's signal dispositions and thread limit.
int cli_main(int argc, char** argv);

int command_run(int argc, char** argv);        ///< shellcontract run IN -o OUT [options]
int command_check(int argc, char** argv);      ///< shellcontract check IN
int command_bench_ccd(int argc, char** argv);  ///< shellcontract bench ccd --queries DIR
int command_regions(int argc, char** argv);    ///< shellcontract regions IN -o OUT.ply
int command_bench_error(int argc, char** argv);  ///< shellcontract bench error IN [options]
int command_reconstruct(int argc, char** argv);  ///< shellcontract reconstruct PTS -o OUT
int command_repair(int argc, char** argv);       ///< shellcontract repair IN -o OUT
int command_sweep(int argc, char** argv);        ///< shellcontract sweep SWEEP.json -o DIR

}  // namespace shellcontract::cli
