// A host that traps floating-point exceptions (feenableexcept(FE_INVALID | FE_DIVBYZERO), a debug
// build's habit) can run the library. Before: the batched (coloured) kernels evaluated their
// divisions on every lane of a batch, and a padding lane, or a lane skipped as at rest, divided
// 0 by 0 (its result masked out afterwards): SIGFPE in such a host, and without traps a sticky
// FE_INVALID flag that a host checking fetestexcept took for its own. Each run is a program of
// its own (tests/tools/fp_trap_run.cpp): the traps must be set before the run's threads start.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <string>
#include <vector>

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

}  // namespace
}  // namespace shellcontract
