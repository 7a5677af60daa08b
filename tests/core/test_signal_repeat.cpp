// core/signal_repeat.hpp: which stop signal is the first one repeated (a wrapper's forward, GNU
// timeout's second send) and which is a second request that ends a run at once. The CLI's own
// tests (tests/cli/test_cli_signals.cpp) send real echoes; the moment a second request ends a
// run cannot be chosen from outside (it may land in a file's creation, which waits), so the rule
// itself is checked here.
#include <gtest/gtest.h>
#include <signal.h>

#include "core/signal_repeat.hpp"

namespace shellcontract {
namespace {

constexpr std::int64_t MS = 1'000'000;

TEST(SignalRepeat, TheSameSignalWithinTheWindowIsTheFirstRepeated) {
  const std::int64_t t0 = 123'456'789'000;
  EXPECT_TRUE(repeats_first_signal(SIGINT, SIGINT, t0, t0));             // the same instant
  EXPECT_TRUE(repeats_first_signal(SIGTERM, SIGTERM, t0, t0 + 1 * MS));  // a forward
  EXPECT_TRUE(repeats_first_signal(SIGHUP, SIGHUP, t0, t0 + SIGNAL_REPEAT_WINDOW_NS - 1));
}

TEST(SignalRepeat, LaterOrAnotherSignalIsASecondRequest) {
  const std::int64_t t0 = 5 * MS;
  EXPECT_FALSE(repeats_first_signal(SIGINT, SIGINT, t0, t0 + SIGNAL_REPEAT_WINDOW_NS));
  EXPECT_FALSE(
      repeats_first_signal(SIGINT, SIGINT, t0, t0 + 2000 * MS));  // a person's second Ctrl-C
  EXPECT_FALSE(repeats_first_signal(SIGTERM, SIGINT, t0, t0));    // another signal at once
  EXPECT_FALSE(repeats_first_signal(SIGINT, SIGTERM, t0, t0 + 1 * MS));
}

}  // namespace
}  // namespace shellcontract
