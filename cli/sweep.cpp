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

}  // namespace

int command_sweep(int argc, char** argv) {
  const fs::path dir = executable_dir();
  // The build tree keeps the package in <build>/python; an install puts it on the interpreter's
  // own path. The sweep runs this same executable for its jobs.
  if (!dir.empty()) {
    const fs::path package = dir / "python";
    if (fs::is_regular_file(package / "shellcontract" / "sweep.py")) {
      const char* old = std::getenv("PYTHONPATH");
      const std::string path = package.string() + (old && *old ? ":" + std::string(old) : "");
      ::setenv("PYTHONPATH", path.c_str(), 1);
    }
    if (!std::getenv("SHELLCONTRACT_CLI"))
      ::setenv("SHELLCONTRACT_CLI", (dir / "shellcontract").c_str(), 1);
  }
  const std::string python = python_interpreter();
  std::vector<std::string> args{python, "-m", "shellcontract.sweep"};
  for (int i = 1; i < argc; ++i) args.emplace_back(argv[i]);
  std::vector<char*> cargs;
  for (std::string& a : args) cargs.push_back(a.data());
  cargs.push_back(nullptr);
  ::execvp(python.c_str(), cargs.data());
  std::cerr << "shellcontract sweep: cannot start " << python << " (" << std::strerror(errno)
            << "); the sweep is `python3 -m shellcontract.sweep` (set SHELLCONTRACT_PYTHON)\n";
  return 1;
}

}  // namespace shellcontract::cli
