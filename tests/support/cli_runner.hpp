// Runs the built `shellcontract` executable (SHELLCONTRACT_CLI_PATH) as a user would, capturing
// its exit code and its output (stdout and stderr together).
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>
#include <vector>

namespace shellcontract::test {

struct RunResult {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr together
};

/// Single-quotes s for /bin/sh.
inline std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// Runs a /bin/sh command line, capturing what it writes to stdout.
inline RunResult run_command(const std::string& cmd) {
  RunResult r;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  std::size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// The command line that runs the CLI with the given arguments, quoted for /bin/sh.
inline std::string cli_line(const std::vector<std::string>& args) {
  std::string cmd = quoted(SHELLCONTRACT_CLI_PATH);
  for (const std::string& a : args) cmd += " " + quoted(a);
  return cmd;
}

/// The command line that runs the CLI with the given arguments, stderr into stdout.
inline std::string cli_command(const std::vector<std::string>& args) {
  return cli_line(args) + " 2>&1";
}

/// Runs the CLI with the given arguments.
inline RunResult run_cli(const std::vector<std::string>& args) {
  return run_command(cli_command(args));
}

/// Runs the CLI with at most `kib` KiB of address space (the shell's ulimit -v, RLIMIT_AS): its
/// allocations beyond that fail with std::bad_alloc, as on a machine without the memory.
inline RunResult run_cli_limited(long kib, const std::vector<std::string>& args) {
  return run_command("ulimit -v " + std::to_string(kib) + " && exec " + cli_command(args));
}

}  // namespace shellcontract::test
