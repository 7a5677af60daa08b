// libFuzzer target for the mesh reader, beside the seeded mutator of
// tests/fuzz/test_reader_fuzz.cpp: coverage-guided, so it finds inputs the mutator's fixed
// mutations do not reach. The contract is the same: whatever the bytes, read_input_mesh returns
// a mesh or throws InputError naming the file. Anything else is a finding: another exception
// (uncaught: abort), a message without the path (abort), a crash, a sanitizer report, a hang
// (-timeout) or an allocation over libFuzzer's -malloc_limit_mb.
//
// The reader picks the format by extension, so each input is read as every format of the table
// (.off, .obj, .ply, .stl, .glb and .gltf; src/mesh/formats.hpp): the corpus is plain mesh files.
// Built with clang (-DSHELLCONTRACT_LIBFUZZER=ON, cmake/ShellContractLibFuzzer.cmake;
// docs/design/testing.md says how to run it), and in the default build without libFuzzer, beside
// replay_main.cpp, which runs it on the seeds and the regression files.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "mesh/formats.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace {

namespace fs = std::filesystem;

/// One folder per fuzzing process (libFuzzer's -jobs and -fork run several), removed at exit.
/// Allocated once and never freed, so that the exit handler can still use it.
const fs::path* g_dir = nullptr;

const fs::path& work_dir() {
  if (!g_dir) {
    g_dir = new fs::path(fs::temp_directory_path() / ("shellcontract_libfuzzer_" + std::to_string(::getpid())));
    fs::create_directories(*g_dir);
    std::atexit([] {
      std::error_code ec;
      fs::remove_all(*g_dir, ec);
    });
  }
  return *g_dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  for (const shellcontract::MeshFormat& format : shellcontract::MESH_FORMATS) {
    const char* ext = format.ext;
    const fs::path path = work_dir() / (std::string("input.") + ext);
    {
      std::ofstream out(path, std::ios::binary | std::ios::trunc);
      out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    try {
      shellcontract::read_input_mesh(path.string());
    } catch (const shellcontract::InputError& e) {
      if (std::string(e.what()).find(path.string()) == std::string::npos) {
        std::fprintf(stderr, "reader_fuzzer: the InputError does not name the file (.%s): %s\n", ext, e.what());
        std::abort();
      }
    }
  }
  return 0;
}
