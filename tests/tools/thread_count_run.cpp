// A run in a process of its own, then the number of the process's threads (/proc/self/task):
// TBB starts its worker threads on the first parallel work outside an arena that has room only
// for its caller, so a run held to one thread must leave the process with one thread
// (tests/sim/test_run_threads.cpp). A test binary has run parallel work before, hence a program.
// Usage: thread_count_run MESH [NAME VALUE]...   (NAME VALUE: set_run_option, as the CLI's --NAME
// VALUE) Prints "STATUS, N frames, T threads"; exit 1 on an error.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iterator>

#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"

int main(int argc, char** argv) {
  using namespace shellcontract;
  if (argc < 2 || argc % 2 != 0) {
    std::fprintf(stderr, "usage: thread_count_run MESH [NAME VALUE]...\n");
    return 1;
  }
  try {
    const Mesh mesh = read_input_mesh(argv[1]);
    RunOptions options;
    for (int i = 2; i < argc; i += 2) set_run_option(options, argv[i], argv[i + 1]);
    const RunResult r = run_contraction(mesh, options);
    const auto threads = std::distance(std::filesystem::directory_iterator("/proc/self/task"),
                                       std::filesystem::directory_iterator());
    std::printf("%s, %d frames, %ld threads\n", status_name(r.status), r.frames_run,
                static_cast<long>(threads));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "thread_count_run: %s\n", e.what());
    return 1;
  }
  return 0;
}
