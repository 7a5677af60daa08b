// The region finder's iterative heat solves run their systems two at a time in one thread
// (src/geometry/heat_smoothing.cpp): each system must get exactly the result it gets alone,
// bit for bit, whatever system it is paired with and however many there are, so the smoothed
// curvature (and the regions) cannot depend on the batching or the threads. The Laplacian and
// the masses are built here, not by the finder. Checked to fail when the paired kernel reads
// the first system's matrix values for both systems.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include <Eigen/SparseCore>
#include <tbb/task_arena.h>

#include "core/cancellation.hpp"
#include "geometry/heat_smoothing.hpp"
#include "support/cancel_probe.hpp"
#include "support/heat_problem.hpp"

namespace shellcontract {
namespace {

using test::HeatProblem;

/// A bumpy icosphere (support/heat_problem.hpp) and a rough field h = z + sin 7x to smooth, at
/// five times (an odd count leaves one system alone).
HeatProblem bumpy_problem() {
  HeatProblem h = test::bumpy_heat_problem(4, 0.1, {4.0, 3.0, 5.0}, 7.0);
  h.times = {1e-4, 4e-4, 2.5e-3, 1e-2, 4e-2};
  return h;
}

bool same_bits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

TEST(HeatBatch, EachSystemGetsTheBitsItGetsAlone) {
  const HeatProblem h = bumpy_problem();
  std::vector<int> together_its;
  const std::vector<Eigen::VectorXd> together = detail::heat_solves(h.L, h.mass, h.rhs, h.times, true, &together_its);
  ASSERT_EQ(together.size(), h.times.size());
  for (std::size_t k = 0; k < h.times.size(); ++k) {
    std::vector<int> alone_its;
    const std::vector<Eigen::VectorXd> alone = detail::heat_solves(h.L, h.mass, h.rhs, {h.times[k]}, true, &alone_its);
    EXPECT_GT(together_its[k], 0) << "time " << k << " fell back to the direct solver";
    EXPECT_EQ(together_its[k], alone_its[0]) << "time " << k;
    EXPECT_TRUE(same_bits(together[k], alone[0])) << "time " << k;
    // And it is the solution (the batching must not change which system is solved).
    const Eigen::VectorXd residual = h.rhs - (h.mass.asDiagonal() * together[k] + h.times[k] * (h.L * together[k]));
    EXPECT_LE(residual.norm(), 1e-10 * h.rhs.norm()) << "time " << k;
  }
}

TEST(HeatBatch, PartnersDoNotMatter) {
  // Rotated by one, the systems are paired with others (the first with the last: t0 with t4
  // and t1 with t3, then t1 with t0 and t2 with t4).
  const HeatProblem h = bumpy_problem();
  const std::size_t n = h.times.size();
  std::vector<double> rotated;
  for (std::size_t k = 0; k < n; ++k) rotated.push_back(h.times[(k + 1) % n]);
  const std::vector<Eigen::VectorXd> plain = detail::heat_solves(h.L, h.mass, h.rhs, h.times, true);
  const std::vector<Eigen::VectorXd> moved = detail::heat_solves(h.L, h.mass, h.rhs, rotated, true);
  for (std::size_t k = 0; k < n; ++k) EXPECT_TRUE(same_bits(plain[(k + 1) % n], moved[k])) << "time " << k;
}

// A run's cancel is heard inside the iterative solves, the longest stage of a large mesh's region
// selection (src/core/cancellation.hpp). Before, they ran to their end. One system: its batch
// runs on the calling thread, which is the one that asks.
TEST(HeatBatch, TheIterativeSolvesAskARunsCancelAtEachIteration) {
  HeatProblem h = bumpy_problem();
  h.times = {1e-2};
  std::vector<int> iterations;
  detail::heat_solves(h.L, h.mass, h.rhs, h.times, true, &iterations);
  ASSERT_GT(iterations.at(0), 3) << "too few iterations to stop in the middle";
  int asked = 0;
  const CancellationScope scope([&] { return ++asked >= 3; });
  EXPECT_THROW(detail::heat_solves(h.L, h.mass, h.rhs, h.times, true), PreparationCancelled);
  EXPECT_EQ(asked, 3);
}

// Below HEAT_DIRECT_MAX_VERTICES each time is one factorization, a call that cannot be
// interrupted, and together they are nearly all of a mesh's region selection. Before, the direct
// solves asked nothing between them: bear split in four (55,298 vertices) heard Ctrl-C only after
// all four. On one thread each factorization is preceded by its own question.
TEST(HeatBatch, TheDirectSolvesAskARunsCancelBeforeEachFactorization) {
  const HeatProblem h = bumpy_problem();
  ASSERT_EQ(h.times.size(), 5u);
  tbb::task_arena one(1);
  one.execute([&] {
    const auto call = [&] { detail::heat_solves(h.L, h.mass, h.rhs, h.times, false); };
    // The set-up's questions and one per factorization.
    EXPECT_GE(test::questions_of_a_whole_call(call), 5 + 2);
    // Stopped before the last factorization: its question, not the end, throws.
    test::expect_heard_inside("the direct heat solves", call, 6);
  });
}

}  // namespace
}  // namespace shellcontract
