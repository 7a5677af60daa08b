// A test that needs what a plain local run may lack (the shared CCD benchmark data, root for a
// mount or a device node) skips there with the reason, but fails under CI (CI=true, as the
// configure's guard of the viewer tests and blender/tests read it): the CI machine runs as root
// beside the shared data, so a skip there would be a test that vanished from the suite meant to
// run it, with ctest still reporting 100 % passed.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>

namespace shellcontract::test {

inline bool under_ci() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && std::strcmp(ci, "true") == 0;
}

}  // namespace shellcontract::test

/// Skips the calling test with `message` (anything that streams), or fails it under CI=true.
#define SKIP_OR_FAIL_UNDER_CI(message)                                          \
  do {                                                                          \
    std::ostringstream why_;                                                    \
    why_ << message;                                                            \
    if (::shellcontract::test::under_ci())                                      \
      GTEST_FAIL() << "CI=true, where this test must run, but: " << why_.str(); \
    GTEST_SKIP() << why_.str();                                                 \
  } while (false)
