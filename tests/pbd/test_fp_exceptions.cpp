// A host that traps floating-point exceptions (feenableexcept(FE_INVALID | FE_DIVBYZERO), a debug
// build's habit) can run the library. Before: the batched (coloured) kernels evaluated their
// divisions on every lane of a batch, and a padding lane, or a lane skipped as at rest, divided
// 0 by 0 (its result masked out afterwards): SIGFPE in such a host, and without traps a sticky
// FE_INVALID flag that a host checking fetestexcept took for its own. Each run is a program of
// its own (tests/tools/fp_trap_run.cpp): the traps must be set before the run's threads start.
// In process, without traps: a batched call gives the caller back its own floating-point state.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cfenv>
#include <csignal>
#include <random>
#include <string>
#include <vector>

#include "material/registry.hpp"
#include "pbd/constraint_batches.hpp"
#include "support/batch_scene.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

/// The wait status of fp_trap_run MESH ARGS... (its stdout and stderr left to the test's).
int trapped_run(const std::string& mesh, const std::vector<std::string>& args) {
  std::vector<std::string> all{SHELLCONTRACT_FP_TRAP_RUN, mesh};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t child = ::fork();
  if (child == 0) {
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  return status;
}

void expect_no_fp_exception(const std::string& mesh, std::vector<std::string> args) {
  std::string what = mesh;
  for (const std::string& a : args) what += " " + a;
  // Coloured: the batched kernels (sequential runs the scalar ones); two threads, so that the
  // workers run them too.
  args.insert(args.end(), {"order", "coloured", "threads", "2", "frames", "3"});
  const int status = trapped_run(mesh, args);
  EXPECT_FALSE(WIFSIGNALED(status) && WTERMSIG(status) == SIGFPE) << what << ": SIGFPE";
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << what << ": wait status " << status;
}

const std::string ICO2 = std::string(test::MESH_DIR) + "/ico2.off";
const std::string BUMPY = std::string(test::MESH_DIR) + "/bumpy_sphere.off";

TEST(FpExceptions, MembraneAndBendingKernels) {
  for (const char* solver : {"xpbd", "pbd"})
    for (const char* bending : {"dihedral", "isometric"})
      expect_no_fp_exception(ICO2, {"solver", solver, "bending", bending});
}

TEST(FpExceptions, EveryMembraneMaterial) {
  for (const char* solver : {"xpbd", "pbd"})
    for (const char* material : {"stvk", "corotated", "linear", "mooney-rivlin"})
      expect_no_fp_exception(ICO2, {"solver", solver, "material", material});
}

TEST(FpExceptions, AnisotropicKernels) {
  for (const char* solver : {"xpbd", "pbd"})
    for (const char* aniso : {"arap", "stvk", "sqrt", "active-fiber"})
      expect_no_fp_exception(BUMPY, {"solver", solver, "aniso", aniso, "regions", "auto"});
}

// The membrane scene's colour 0 holds a triangle at rest (E = 0) and one with every vertex pinned
// (G = 0): lanes whose division is 0 / 0 unless guarded. The call must raise no flag of its own
// (a host checking fetestexcept afterwards would take it for its own) and keep the caller's flags
// and rounding mode as they were.
TEST(FpExceptions, BatchedCallKeepsTheCallersFlagsAndAddsNone) {
  std::mt19937 rng(32);
  test::MembraneScene s = test::membrane_scene(8, rng);
  const ColouredBatches<MembraneBatch> b = make_membrane_batches(s.records, s.colours);
  const Stvk material(MaterialParams{1.0, 1.0});
  for (const bool xpbd : {false, true}) {
    std::vector<double> x = s.x0;
    std::vector<PaddedVertex> xw = test::padded(s);
    const ProjectionContext ctx = test::context(x, s.w);
    std::vector<double> lambda(BATCH_LANES * b.batches.size(), 0.0);
    std::feclearexcept(FE_ALL_EXCEPT);
    std::feraiseexcept(FE_OVERFLOW);  // the caller's own, from before the call
    ASSERT_EQ(std::fesetround(FE_UPWARD), 0);
    project_stvk_membrane_batches(material, b.batches.data(), b.batches.size(), xw.data(), ctx,
                                  xpbd ? lambda.data() : nullptr, BatchIsa::Auto);
    const int raised = std::fetestexcept(FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW);
    const int round = std::fegetround();
    std::fesetround(FE_TONEAREST);
    std::feclearexcept(FE_ALL_EXCEPT);
    EXPECT_EQ(raised, FE_OVERFLOW) << (xpbd ? "xpbd" : "pbd") << ": flags after the call";
    EXPECT_EQ(round, FE_UPWARD) << (xpbd ? "xpbd" : "pbd");
  }
}

}  // namespace
}  // namespace shellcontract
