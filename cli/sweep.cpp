// shellcontract sweep: the front of `python3 -m shellcontract.sweep` (python/shellcontract/
// sweep.py), which runs the jobs of a sweep file on Dask distributed, each as `shellcontract run`.
// The engine is in Python because Dask is; this only finds the interpreter and the package and
// replaces the process with it, so signals (Ctrl-C) and the exit code are the sweep's own.
#include <sys/wait.h>
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

/// Whether `python` runs Python: it is asked to print a word and must print exactly that, exit 0.
/// Only an interpreter the user named ($SHELLCONTRACT_PYTHON) is asked: once the process is
/// replaced by it nothing here can speak, and one that is not Python ended the sweep unexplained
/// (/bin/false: exit 1, /bin/true: exit 0 with nothing run). `why` says what it did instead.
bool runs_python(const std::string& python, std::string& why) {
  int fds[2];
  if (::pipe(fds) != 0) return true;  // cannot ask: the exec below says what it can
  const std::string word = "shellcontract-sweep-python";
  const std::string code = "import sys; sys.stdout.write('" + word + "')";
  std::vector<std::string> args{python, "-c", code};
  std::vector<char*> cargs;
  for (std::string& a : args) cargs.push_back(a.data());
  cargs.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return true;
  }
  if (pid == 0) {
    ::dup2(fds[1], 1);
    ::close(fds[0]);
    ::close(fds[1]);
    ::execvp(python.c_str(), cargs.data());
    ::_exit(127);
  }
  ::close(fds[1]);
  std::string out;
  char buf[256];
  for (;;) {
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0 || out.size() > 4096) break;
    out.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && out == word) return true;
  // Not started (the child's exec failed): the exec below fails too, and says why.
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127 && out.empty()) return true;
  if (WIFEXITED(status))
    why = "asked to run a line of Python, it exited " + std::to_string(WEXITSTATUS(status)) +
          (out == word   ? std::string()
           : out.empty() ? " without printing it"
                         : " printing something else");
  else
    why = "asked to run a line of Python, it was killed by signal " +
          std::to_string(WTERMSIG(status));
  return false;
}

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
  if (const char* named = std::getenv("SHELLCONTRACT_PYTHON"); named && *named) {
    std::string why;
    if (!runs_python(python, why)) {
      std::cerr << "shellcontract sweep: SHELLCONTRACT_PYTHON=" << python
                << " is not a Python interpreter (" << why
                << "); nothing run: the sweep is `python3 -m shellcontract.sweep`, set "
                << "SHELLCONTRACT_PYTHON to a python3 with the shellcontract package and Dask's "
                << "distributed, or unset it\n";
      return 1;
    }
  }
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
