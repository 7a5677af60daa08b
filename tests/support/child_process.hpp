// A program started as a child process that a test talks to while it runs: its stderr read from a
// pipe (wait for a line, collect the rest), signals sent to it, its wait status read. For the
// CLI tests that interrupt a run; cli_runner.hpp serves the runs that are only started and read.
//
// Guarantees:
// - The child starts as a shell starts a job, whatever the test runner's own state: the signals
//   these tests send or meet (SIGINT, SIGTERM, SIGHUP, SIGUSR1, SIGPIPE, SIGXFSZ) at their
//   default action and no signal blocked (a disposition or mask inherited from whoever started
//   the tests would otherwise change what the run does with them).
// - It is started with fork, so it begins as a copy of this process (its memory included, which
//   test_cli_run_control's peak-memory test relies on), and between fork and exec it makes only
//   async-signal-safe calls: its arguments and environment are prepared before the fork.
// - No wait blocks without bound: each has a timeout (CHILD_TIMEOUT unless given, far beyond
//   what any run of these tests takes), so a child that hangs fails its test instead of the suite.
// - A test that fails (an ASSERT that returns early, a timeout) leaves no child running: the
//   destructor kills a child not yet reaped (SIGKILL) and reaps it, and closes the pipe.
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

extern char** environ;

namespace shellcontract::test {

/// How long a wait for a child's output or its end may take unless the call says otherwise.
inline constexpr std::chrono::seconds CHILD_TIMEOUT{600};

/// Where the child's stdout goes.
enum class ChildOut {
  Inherit,  ///< this process's stdout
  DevNull,
  File,    ///< ChildSpec::out_file, created or truncated (mode 0644)
  Closed,  ///< no stdout at all: every write fails with EBADF
};

/// Where the child's stderr goes.
enum class ChildErr {
  Inherit,  ///< this process's stderr
  DevNull,
  Pipe,        ///< a pipe that Child reads (await, finish, output)
  ClosedPipe,  ///< a pipe whose reading end is closed before the fork: no process holds it, so
               ///< every write fails (EPIPE, and SIGPIPE unless ignored) from the first one on
};

/// What to start and how.
struct ChildSpec {
  std::string program;            ///< the executable's path (no PATH search); also argv[0]
  std::vector<std::string> args;  ///< the arguments after argv[0]
  ChildOut out = ChildOut::DevNull;
  std::string out_file;  ///< with ChildOut::File
  ChildErr err = ChildErr::Pipe;
  std::vector<std::pair<std::string, std::string>> env;  ///< set in the child's environment
  std::optional<rlim_t> file_size_limit;  ///< RLIMIT_FSIZE in bytes, soft and hard (`ulimit -f`)
  bool ignore_xfsz = false;               ///< SIGXFSZ ignored (`trap '' XFSZ`) after the reset
};

/// The built CLI (SHELLCONTRACT_CLI_PATH) with `args`; stdout to /dev/null, stderr to a pipe.
inline ChildSpec cli_child(std::vector<std::string> args) {
  ChildSpec spec;
  spec.program = SHELLCONTRACT_CLI_PATH;
  spec.args = std::move(args);
  return spec;
}

/// /bin/bash -c `command`; stdout to /dev/null, stderr to a pipe. A command that ends with `exec`
/// of the CLI makes the child's pid the CLI's, so that a signal reaches the run itself.
inline ChildSpec bash_child(const std::string& command) {
  ChildSpec spec;
  spec.program = "/bin/bash";
  spec.args = {"-c", command};
  return spec;
}

#ifdef SHELLCONTRACT_HELD_CLI
/// As cli_child; `hold_ms` > 0 runs the CLI's code through held_cli (tests/tools/held_cli.cpp),
/// which holds each temporary that long right after its creation and says so on stderr.
inline ChildSpec held_cli_child(std::vector<std::string> args, int hold_ms) {
  if (hold_ms <= 0) return cli_child(std::move(args));
  ChildSpec spec;
  spec.program = SHELLCONTRACT_HELD_CLI;
  spec.args = {std::to_string(hold_ms)};
  spec.args.insert(spec.args.end(), args.begin(), args.end());
  return spec;
}
#endif

/// "exit N" or "ended by signal N", for messages.
inline std::string ending(int status) {
  return WIFEXITED(status)
             ? "exit " + std::to_string(WEXITSTATUS(status))
             : "ended by signal " + std::to_string(WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

/// A started child. Not copyable; moving it moves the ownership of the process.
class Child {
 public:
  Child() = default;
  /// Starts `spec`; pid() is -1 when it could not be (pipe or fork failed). A program that
  /// cannot be executed ends with exit code 127.
  explicit Child(const ChildSpec& spec) { start(spec); }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  Child(Child&& other) noexcept { take(other); }
  Child& operator=(Child&& other) noexcept {
    if (this != &other) {
      stop();
      take(other);
    }
    return *this;
  }
  /// Kills (SIGKILL) and reaps a child not yet reaped; closes the pipe.
  ~Child() { stop(); }

  pid_t pid() const { return pid_; }
  /// Whether finish() has collected the child's status.
  bool reaped() const { return reaped_; }
  /// Everything read from the stderr pipe so far.
  const std::string& output() const { return output_; }

  /// Sends `sig` to the child (nothing once it is reaped: the pid may be another process's).
  void signal(int sig) const {
    if (pid_ > 0 && !reaped_) ::kill(pid_, sig);
  }

  /// Reads the stderr pipe into output() until `text` stands there `count` times (overlapping
  /// ones counted, from the start of the output). False: the pipe ended first (the child closed
  /// it or exited), or `timeout` passed; the child is left running either way.
  bool await(const std::string& text, int count = 1,
             std::chrono::milliseconds timeout = CHILD_TIMEOUT) {
    const auto deadline = Clock::now() + timeout;
    for (;;) {
      std::size_t found = 0;
      for (std::size_t at = output_.find(text); at != std::string::npos;
           at = output_.find(text, at + 1))
        ++found;
      if (static_cast<int>(found) >= count) return true;
      if (read_some(deadline) <= 0) return false;
    }
  }

  /// Reads the rest of the stderr pipe into output() (so that the child never blocks on it) and
  /// waits for the child's end; returns its wait status. After `timeout` the child is killed
  /// (SIGKILL) and reaped, a test failure is recorded, and the status says SIGKILL. Called again,
  /// the same status; -1 where no child started.
  int finish(std::chrono::milliseconds timeout = CHILD_TIMEOUT) {
    if (reaped_) return status_;
    if (pid_ <= 0) return -1;
    const auto deadline = Clock::now() + timeout;
    while (fd_ >= 0 && read_some(deadline) > 0) {
    }
    close_pipe();
    for (;;) {
      const pid_t got = ::waitpid(pid_, &status_, WNOHANG);
      if (got == pid_) {
        reaped_ = true;
        return status_;
      }
      if (got < 0 && errno != EINTR) {
        ADD_FAILURE() << "waitpid(" << pid_ << ") failed: errno " << errno;
        pid_ = -1;
        return -1;
      }
      if (Clock::now() >= deadline) {
        ADD_FAILURE() << program_ << " (pid " << pid_ << ") did not end within "
                      << timeout.count() / 1000.0 << " s; killed";
        stop();
        return status_;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }

 private:
  using Clock = std::chrono::steady_clock;

  void start(const ChildSpec& spec) {
    program_ = spec.program;
    // Everything the child needs, made before the fork: after it only async-signal-safe calls.
    std::vector<std::string> argv_text{spec.program};
    argv_text.insert(argv_text.end(), spec.args.begin(), spec.args.end());
    std::vector<char*> argv;
    for (std::string& a : argv_text) argv.push_back(a.data());
    argv.push_back(nullptr);
    std::vector<std::string> env_text;
    for (char** e = environ; *e != nullptr; ++e) {
      const std::string entry = *e;
      bool replaced = false;
      for (const auto& [name, value] : spec.env)
        replaced = replaced || entry.compare(0, name.size() + 1, name + "=") == 0;
      if (!replaced) env_text.push_back(entry);
    }
    for (const auto& [name, value] : spec.env) env_text.push_back(name + "=" + value);
    std::vector<char*> envp;
    for (std::string& e : env_text) envp.push_back(e.data());
    envp.push_back(nullptr);

    // Close-on-exec: the child keeps only its own stderr (dup2 clears the flag on fd 2), and no
    // other child started meanwhile holds this pipe open.
    int fds[2] = {-1, -1};
    const bool piped = spec.err == ChildErr::Pipe || spec.err == ChildErr::ClosedPipe;
    if (piped && ::pipe2(fds, O_CLOEXEC) != 0) return;
    if (spec.err == ChildErr::ClosedPipe) {
      ::close(fds[0]);
      fds[0] = -1;
    }
    const pid_t pid = ::fork();
    if (pid == 0) {
      const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
      if (spec.out == ChildOut::DevNull) ::dup2(null, 1);
      if (spec.out == ChildOut::Closed) ::close(1);
      if (spec.out == ChildOut::File)
        ::dup2(::open(spec.out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644), 1);
      if (spec.err == ChildErr::DevNull) ::dup2(null, 2);
      if (piped) ::dup2(fds[1], 2);
      for (const int sig : {SIGINT, SIGTERM, SIGHUP, SIGUSR1, SIGPIPE, SIGXFSZ})
        ::signal(sig, SIG_DFL);
      if (spec.ignore_xfsz) ::signal(SIGXFSZ, SIG_IGN);
      sigset_t none;
      ::sigemptyset(&none);
      ::sigprocmask(SIG_SETMASK, &none, nullptr);
      if (spec.file_size_limit) {
        const struct rlimit lim { *spec.file_size_limit, *spec.file_size_limit };
        ::setrlimit(RLIMIT_FSIZE, &lim);
      }
      ::execve(argv[0], argv.data(), envp.data());
      ::_exit(127);
    }
    if (piped) ::close(fds[1]);
    if (pid < 0) {
      if (fds[0] >= 0) ::close(fds[0]);
      return;
    }
    pid_ = pid;
    fd_ = fds[0];
  }

  /// One read of the pipe into output_, waiting at most until `deadline`: the bytes read, 0 at
  /// its end (or with no pipe), -1 at the deadline or on an error.
  ssize_t read_some(Clock::time_point deadline) {
    if (fd_ < 0) return 0;
    char buf[512];
    for (;;) {
      const auto now = Clock::now();
      if (now >= deadline) return -1;
      // Rounded up: a wait never ends before its deadline.
      const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - now).count();
      pollfd p{fd_, POLLIN, 0};
      const int ready = ::poll(&p, 1, static_cast<int>(std::min<long long>(left, 1000)));
      if (ready < 0 && errno != EINTR) return -1;
      if (ready <= 0) continue;
      const ssize_t n = ::read(fd_, buf, sizeof buf);
      if (n < 0 && errno == EINTR) continue;
      if (n > 0) output_.append(buf, static_cast<std::size_t>(n));
      return n;
    }
  }

  void close_pipe() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

  void stop() {
    close_pipe();
    if (pid_ > 0 && !reaped_) {
      ::kill(pid_, SIGKILL);
      while (::waitpid(pid_, &status_, 0) < 0 && errno == EINTR) {
      }
      reaped_ = true;
    }
  }

  void take(Child& other) {
    pid_ = std::exchange(other.pid_, -1);
    fd_ = std::exchange(other.fd_, -1);
    reaped_ = std::exchange(other.reaped_, false);
    status_ = other.status_;
    output_ = std::move(other.output_);
    program_ = std::move(other.program_);
  }

  pid_t pid_ = -1;
  int fd_ = -1;
  bool reaped_ = false;
  int status_ = 0;
  std::string output_;
  std::string program_;
};

}  // namespace shellcontract::test
