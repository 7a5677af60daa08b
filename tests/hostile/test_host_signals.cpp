// A host program with signal handling of its own (include/shellcontract/signals.hpp): it can
// keep the library off its signals' dispositions and remove the temporaries itself. Before, the
// library's first write installed its handler for SIGINT, SIGTERM, SIGHUP and SIGUSR1 with no
// way out, and a host that took the signals in a sigwait thread (its own handling, where the
// library's handler never runs) left the temporary of a write in progress behind.
// The host is tests/tools/signal_host.cpp, started as a test::Child: killed and reaped if a test
// fails, and no wait for it without a time limit.
#include <sys/wait.h>

#include <csignal>
#include <sstream>
#include <string>
#include <vector>

#include "hostile/hostile_support.hpp"
#include "support/child_process.hpp"

namespace shellcontract {
namespace {

using test::Hostile;

/// signal_host MODE DIR [keep]; what it prints comes on its stderr, which the Child reads.
test::ChildSpec host_spec(const std::string& mode, const fs::path& dir, bool keep = false) {
  test::ChildSpec spec;
  spec.program = SHELLCONTRACT_SIGNAL_HOST;
  spec.args = {mode, dir.string()};
  if (keep) spec.args.push_back("keep");
  return spec;
}

/// The lines of `text`, without their "\n".
std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> all;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) all.push_back(line);
  return all;
}

// Before: the first write gave each of the four signals the library's handler; there was no
// opt-out. With set_signal_cleanup(false) first, a fresh process's write leaves all four at
// their default action.
TEST_F(Hostile, AHostThatOptsOutKeepsItsSignalDispositionsThroughAWrite) {
  test::Child kept(host_spec("dispositions", dir_, true));
  const int kept_status = kept.finish();
  ASSERT_EQ(kept_status, 0) << test::ending(kept_status) << "\n" << kept.output();
  ASSERT_EQ(lines(kept.output()), std::vector<std::string>(4, "changed"))
      << "without the opt-out the library's handler must be installed, or this cannot fail";
  fs::remove(dir_ / "o.txt");

  test::Child host(host_spec("dispositions", dir_));
  const int status = host.finish();
  EXPECT_EQ(status, 0) << test::ending(status) << "\n" << host.output();
  EXPECT_EQ(lines(host.output()), std::vector<std::string>(4, "default"))
      << "SIGINT, SIGTERM, SIGHUP, SIGUSR1";
  EXPECT_EQ(test::slurp(dir_ / "o.txt"), "data");
}

// Before: a host that blocks the signals and takes them with sigwait (the library's handler never
// runs) had no way to remove a write's temporary: SIGTERM in the middle of a write left it in
// the output's folder. Its signal thread now calls remove_temporaries before it exits.
TEST_F(Hostile, ASigwaitHostRemovesTheTemporaryOfAWriteInProgress) {
  test::Child host(host_spec("sigwait", dir_));
  ASSERT_TRUE(host.await("\n")) << "the host never began its write: " << host.output();
  ASSERT_EQ(host.output(), "writing\n");
  ASSERT_EQ(test::listing(dir_).size(), 1u) << "the write's temporary";
  host.signal(SIGTERM);
  const int status = host.finish();
  ASSERT_TRUE(WIFEXITED(status)) << test::ending(status) << "\n" << host.output();
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM) << "the host's signal thread ends it";
  EXPECT_TRUE(test::listing(dir_).empty()) << "left behind: " << test::listing(dir_).front();
}

// Opting out after the library's handler was installed takes it back where it is still there:
// the default action again for SIGTERM, the host's own handler (set since) kept for SIGHUP. And
// after remove_temporaries every write fails rather than leave a file (the process is ending).
// In the host (signal_host take-back, which prints each check that fails): both change the
// whole process.
TEST_F(Hostile, OptingOutLaterTakesBackOnlyTheLibrarysHandler) {
  test::Child host(host_spec("take-back", dir_));
  const int status = host.finish();
  ASSERT_TRUE(WIFEXITED(status)) << test::ending(status) << "\n" << host.output();
  EXPECT_EQ(WEXITSTATUS(status), 0) << host.output();
  EXPECT_EQ(test::listing(dir_), (std::vector<std::string>{"a.txt", "b.txt"}));
}

}  // namespace
}  // namespace shellcontract
