// Probes of a call's cancellation points (core/cancellation.hpp): count the questions a whole
// call asks a CancellationScope, and check that it stops where the scope first says cancelled.
// A call that stops at the n-th question, where a whole call asks more, stopped before its end.
#pragma once

#include <gtest/gtest.h>

#include <functional>

#include "core/cancellation.hpp"

namespace shellcontract::test {

/// How many times `call` asks a scope that never says cancelled.
inline int questions_of_a_whole_call(const std::function<void()>& call) {
  int asked = 0;
  const CancellationScope scope([&] {
    ++asked;
    return false;
  });
  call();
  return asked;
}

/// True when `call` throws PreparationCancelled at the `at`-th question of a scope that says
/// cancelled from then on.
inline bool stops_at(int at, const std::function<void()>& call) {
  int asked = 0;
  const CancellationScope scope([&] { return ++asked >= at; });
  try {
    call();
  } catch (const PreparationCancelled&) {
    return asked == at;
  }
  return false;
}

/// A call that asks more than `inside` times stops at its first and at its `inside`-th
/// question: it is heard at its start and inside it.
inline void expect_heard_inside(const char* what, const std::function<void()>& call, int inside) {
  const int whole = questions_of_a_whole_call(call);
  EXPECT_GT(whole, inside) << what << " asks " << whole << " times";
  EXPECT_TRUE(stops_at(1, call)) << what << ": a cancel at its start";
  EXPECT_TRUE(stops_at(inside, call)) << what << ": a cancel inside it";
}

}  // namespace shellcontract::test
