// Writes the material tests' textured octahedron (tests/support/textured_octahedron.hpp) for
// the glTF validator's sample runs (CTest fixture): OUTDIR/NAME.obj, OUTDIR/NAME.mtl, OUTDIR/tex.png.
// Usage: write_textured_obj OUTDIR NAME
#include <filesystem>
#include <iostream>

#include "support/textured_octahedron.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: write_textured_obj OUTDIR NAME\n";
    return 1;
  }
  std::filesystem::create_directories(argv[1]);
  std::cout << shellcontract::test::write_textured_octahedron(argv[1], argv[2], true) << '\n';
  return 0;
}
