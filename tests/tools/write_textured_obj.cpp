// Writes the material tests' textured OBJs for the glTF validator's sample runs (CTest fixture):
// the textured octahedron (tests/support/textured_octahedron.hpp: OUTDIR/NAME.obj, NAME.mtl,
// tex.png) or, with `materials`, the sphere whose faces use several materials
// (tests/support/multi_material_sphere.hpp: OUTDIR/NAME.obj, NAME.mtl, skin.png).
// Usage: write_textured_obj OUTDIR NAME [materials]
#include <filesystem>
#include <iostream>
#include <string>

#include "support/multi_material_sphere.hpp"
#include "support/textured_octahedron.hpp"

int main(int argc, char** argv) {
  const bool materials = argc == 4 && std::string(argv[3]) == "materials";
  if (argc != 3 && !materials) {
    std::cerr << "usage: write_textured_obj OUTDIR NAME [materials]\n";
    return 1;
  }
  std::filesystem::create_directories(argv[1]);
  std::cout << (materials ? shellcontract::test::write_multi_material_sphere(argv[1], argv[2])
                          : shellcontract::test::write_textured_octahedron(argv[1], argv[2], true))
            << '\n';
  return 0;
}
