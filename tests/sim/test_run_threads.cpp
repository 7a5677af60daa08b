// A run held to one thread (`threads` 1) prepares on one thread too: its planning (the automatic
// regions, the contact distance) and the Simulator's construction ran outside the run's arena, in
// TBB's default one, which starts a worker per further core of the affinity whatever `threads`
// or a CPU quota said (core/arena_threads.hpp). Counted in a process of its own
// (tests/tools/thread_count_run.cpp): TBB starts its workers at the first parallel work outside an
// arena with room for its caller only, and keeps them.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "core/usable_cpus.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

std::string output_of(const std::string& command) {
  std::string out;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return out;
  char buf[256];
  while (std::fgets(buf, sizeof buf, pipe) != nullptr) out += buf;
  ::pclose(pipe);
  return out;
}

TEST(RunThreads, ARunOnOneThreadPreparesOnOneThread) {
  if (usable_cpus() < 2) GTEST_SKIP() << "one CPU: TBB's default arena has no worker either";
  const std::string run = std::string(SHELLCONTRACT_THREAD_COUNT_RUN) + " " + test::MESH_DIR +
                          "/bumpy_sphere.off regions auto frames 0 threads ";
  // Two threads: the default arena's workers (the control, so that the count can tell).
  const std::string two = output_of(run + "2");
  EXPECT_NE(two.find(", 0 frames, "), std::string::npos) << two;
  EXPECT_EQ(two.find(", 1 threads"), std::string::npos) << two;
  const std::string one = output_of(run + "1");
  EXPECT_NE(one.find(", 0 frames, 1 threads"), std::string::npos) << one;
}

}  // namespace
}  // namespace shellcontract
