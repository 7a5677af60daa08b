// Puts the meshes of several frames of one run into an animated .glb, with the displacement from
// the first to the last frame as a colour field: a stand-in for `run --gltf` until the CLI writes
// it (the README's screenshot was made with it from runs of 0, 20, ..., 200 frames).
// Usage: assemble_gltf OUT.glb FRAME:MESH [FRAME:MESH ...]   (frames increasing, same connectivity)
#include <iostream>
#include <string>

#include "../export/export_fixtures.hpp"
#include "shellcontract/export.hpp"

int main(int argc, char** argv) {
  using namespace shellcontract;
  if (argc < 3) {
    std::cerr << "usage: assemble_gltf OUT.glb FRAME:MESH [FRAME:MESH ...]\n";
    return 1;
  }
  try {
    GltfAnimation a;
    for (int i = 2; i < argc; ++i) {
      const std::string arg = argv[i];
      const std::size_t colon = arg.find(':');
      if (colon == std::string::npos)
        throw std::invalid_argument("expected FRAME:MESH, got '" + arg + "'");
      const Mesh mesh = read_input_mesh(arg.substr(colon + 1));
      if (i == 2) a.faces = test::faces_of(mesh);
      a.frame_numbers.push_back(std::stoi(arg.substr(0, colon)));
      a.frames.push_back(positions_from_mesh(mesh));
    }
    a.colour_fields.push_back(
        {"displacement_first_to_last", (a.frames.back() - a.frames.front()).rowwise().norm()});
    const GltfStats s = write_gltf_animation(argv[1], a);
    std::cout << argv[1] << ": " << a.frames.size() << " frames, " << s.bytes << " bytes\n";
  } catch (const std::exception& e) {
    std::cerr << "assemble_gltf: " << e.what() << '\n';
    return 2;
  }
  return 0;
}
