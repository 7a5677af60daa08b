// A run in a host that traps floating-point exceptions (feenableexcept, as debug builds of DCC
// hosts do): FE_INVALID and FE_DIVBYZERO raise SIGFPE, here and on every thread the run starts
// (a thread inherits them). Enabled before anything else, so that reading the mesh counts too;
// exec resets them, hence a program of its own rather than a run of the CLI.
// Usage: fp_trap_run MESH [NAME VALUE]...   (NAME VALUE: set_run_option, as the CLI's --NAME VALUE)
// Exit 0: the run ended (any status) with no exception raised; SIGFPE otherwise; 1: a usage error.
#include <cfenv>
#include <cstdio>
#include <exception>

#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"

int main(int argc, char** argv) {
  using namespace shellcontract;
  if (argc < 2 || argc % 2 != 0) {
    std::fprintf(stderr, "usage: fp_trap_run MESH [NAME VALUE]...\n");
    return 1;
  }
  std::feclearexcept(FE_ALL_EXCEPT);
  feenableexcept(FE_INVALID | FE_DIVBYZERO);
  try {
    const Mesh mesh = read_input_mesh(argv[1]);
    RunOptions options;
    for (int i = 2; i < argc; i += 2) set_run_option(options, argv[i], argv[i + 1]);
    const RunResult r = run_contraction(mesh, options);
    std::printf("%s, %d frames\n", status_name(r.status), r.frames_run);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fp_trap_run: %s\n", e.what());
    return 1;
  }
  return 0;
}
