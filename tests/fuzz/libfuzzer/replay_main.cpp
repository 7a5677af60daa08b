// Runs reader_fuzzer.cpp's entry point, built without libFuzzer, on the seed files of
// tests/fuzz/fuzz_inputs.hpp and on every file of the folders given (the regression files): the
// default build's check of the fuzz target. It links the reader's objects alone
// (shellcontract_reader, CMakeLists.txt), so a reader that needs a file outside that list fails
// here, in the default build, and not only in the clang build of the libFuzzer target. A finding
// aborts, as it does under libFuzzer.
// Usage: reader_fuzzer_replay [DIR...]
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz/fuzz_inputs.hpp"
#include "mesh/formats.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

void run_one(const std::string& bytes) {
  LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t n = 0;
  for (const shellcontract::test::SeedFile& s : shellcontract::test::seed_files()) {
    run_one(s.bytes);
    ++n;
  }
  for (int i = 1; i < argc; ++i) {
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(argv[i]))
      if (e.is_regular_file()) files.push_back(e.path());
    if (files.empty()) {
      std::fprintf(stderr, "reader_fuzzer_replay: no files in %s\n", argv[i]);
      return 1;
    }
    std::sort(files.begin(), files.end());
    for (const std::filesystem::path& f : files) {
      std::ifstream in(f, std::ios::binary);
      run_one(std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()));
      ++n;
    }
  }
  std::printf("reader_fuzzer_replay: %zu inputs, each read as %s\n", n,
              shellcontract::extension_list(shellcontract::any_format, ".", " and ").c_str());
  return 0;
}
