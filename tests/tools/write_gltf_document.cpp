// Writes the glTF document fixture (tests/support/gltf_document_parts.hpp) as OUTDIR/NAME.glb,
// the input of a sample run whose .glb result (the input's document with new positions) the
// glTF validator checks (CTest fixture).
// Usage: write_gltf_document OUTDIR NAME
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "support/gltf_document_parts.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: write_gltf_document OUTDIR NAME\n";
    return 1;
  }
  std::filesystem::create_directories(argv[1]);
  const std::string path = std::string(argv[1]) + "/" + argv[2] + ".glb";
  std::ofstream out(path, std::ios::binary);
  out << shellcontract::test::glb_bytes(shellcontract::test::document_parts());
  if (!out.flush()) {
    std::cerr << "write_gltf_document: cannot write " << path << '\n';
    return 2;
  }
  std::cout << path << '\n';
  return 0;
}
