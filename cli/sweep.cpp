// shellcontract sweep: the front of `python3 -m shellcontract.sweep` (python/shellcontract/
// sweep.py), which runs the jobs of a sweep file on Dask distributed, each as `shellcontract run`.
// The engine is in Python because Dask is; this only finds the interpreter and the package and
// replaces the process with it, so signals (Ctrl-C) and the exit code are the sweep's own.
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"

#ifndef SHELLCONTRACT_PYTHON_DIR_FROM_BIN
#define SHELLCONTRACT_PYTHON_DIR_FROM_BIN "../lib/python3/dist-packages"
#endif

namespace shellcontract::cli {
namespace {

namespace fs = std::filesystem;

/// $SHELLCONTRACT_PYTHON, else Debian's /usr/bin/python3 (the interpreter the module is built
/// for, with Debian's python3-distributed), else python3 on PATH.
std::string python_interpreter() {
  if (const char* p = std::getenv("SHELLCONTRACT_PYTHON"); p && *p) return p;
  if (::access("/usr/bin/python3", X_OK) == 0) return "/usr/bin/python3";
  return "python3";
}

/// The folder holding this executable (/proc/self/exe), or "" where that is unknown.
fs::path executable_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

/// Where the package may be, relative to this executable: the build tree keeps it in
/// <build>/python, `cmake --install` puts it in <prefix>/SHELLCONTRACT_PYTHON_INSTALL_DIR
/// (cmake/ShellContractPython.cmake), which the build computes relative to <prefix>/bin.
std::vector<fs::path> package_candidates(const fs::path& dir) {
  if (dir.empty()) return {};
  const fs::path installed(SHELLCONTRACT_PYTHON_DIR_FROM_BIN);
  return {dir / "python",
          installed.is_absolute() ? installed : (dir / installed).lexically_normal()};
}

// Run by the interpreter instead of `-m shellcontract.sweep`, so that a package it cannot import
// is said in words (sys.argv[1] is the text saying where it was looked for) rather than as
// "No module named 'shellcontract'".
// The current folder (sys.path[0], '' under -c) is dropped: the package is the one found next to
// this executable or on PYTHONPATH, not a shellcontract/ folder where the sweep is started (the
// source tree's python/, which has no compiled module).
constexpr const char* BOOTSTRAP = R"(import sys
if sys.path and sys.path[0] == "":
    del sys.path[0]
looked = sys.argv.pop(1)
try:
    from shellcontract import sweep
except ImportError as e:
    sys.stderr.write("shellcontract sweep: {} cannot import the Python package shellcontract "
                     "({}); {}\n".format(sys.executable, e, looked))
    sys.exit(1)
sys.exit(sweep.main())
)";

}  // namespace

int command_sweep(int argc, char** argv) {
  const fs::path dir = executable_dir();
  // The sweep runs this same executable for its jobs (unless SHELLCONTRACT_CLI names another).
  std::string looked = "looked for it";
  bool found = false;
  const std::vector<fs::path> candidates = package_candidates(dir);
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    looked += (i == 0 ? " in " : " and in ") + candidates[i].string();
    if (found) continue;
    std::error_code ec;
    if (fs::is_regular_file(candidates[i] / "shellcontract" / "sweep.py", ec)) {
      found = true;
      const char* old = std::getenv("PYTHONPATH");
      const std::string path = candidates[i].string() + (old && *old ? ":" + std::string(old) : "");
      ::setenv("PYTHONPATH", path.c_str(), 1);
    }
  }
  if (!dir.empty() && !std::getenv("SHELLCONTRACT_CLI"))
    ::setenv("SHELLCONTRACT_CLI", (dir / "shellcontract").c_str(), 1);
  looked += std::string(candidates.empty() ? "" : " (next to this executable),") +
            " then on the interpreter's path (PYTHONPATH): install it with the executable "
            "(cmake --install puts both under the prefix), or set PYTHONPATH to the folder "
            "holding shellcontract/; the module must be built for this interpreter "
            "(SHELLCONTRACT_PYTHON chooses another)";
  const std::string python = python_interpreter();
  std::vector<std::string> args{python, "-c", BOOTSTRAP, looked};
  for (int i = 1; i < argc; ++i) args.emplace_back(argv[i]);
  std::vector<char*> cargs;
  for (std::string& a : args) cargs.push_back(a.data());
  cargs.push_back(nullptr);
  ::execvp(python.c_str(), cargs.data());
  std::cerr << "shellcontract sweep: cannot start the Python interpreter " << python << " ("
            << std::strerror(errno) << "); the sweep is `python3 -m shellcontract.sweep` "
            << "(SHELLCONTRACT_PYTHON names the interpreter)\n";
  return 1;
}

}  // namespace shellcontract::cli
