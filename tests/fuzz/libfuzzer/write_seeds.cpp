// Writes the fuzzing seed files of tests/fuzz/fuzz_inputs.hpp (the octahedron in every format
// and PLY variant) into a folder: the seed corpus of reader_fuzzer, with tests/data/fuzz.
// Usage: write_seeds DIR
#include <filesystem>
#include <fstream>
#include <iostream>

#include "fuzz/fuzz_inputs.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: write_seeds DIR\n";
    return 1;
  }
  const std::filesystem::path dir = argv[1];
  std::filesystem::create_directories(dir);
  for (const shellcontract::test::SeedFile& s : shellcontract::test::seed_files()) {
    std::ofstream out(dir / (s.name + "." + s.ext), std::ios::binary);
    out.write(s.bytes.data(), static_cast<std::streamsize>(s.bytes.size()));
    if (!out) {
      std::cerr << "write_seeds: cannot write " << (dir / s.name).string() << "\n";
      return 1;
    }
  }
  return 0;
}
