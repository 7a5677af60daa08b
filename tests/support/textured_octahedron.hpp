// A small closed textured OBJ for the glTF material tests and the validator's sample: an
// octahedron with one texture coordinate per vertex, `usemtl skin`, a .mtl with Kd, d and
// map_Kd (with options before the file name), and a 2 x 2 RGB PNG written as bytes.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace shellcontract::test {

/// A valid 2 x 2 RGB PNG (red, green / blue, white).
inline const std::vector<unsigned char>& tiny_png() {
  static const std::vector<unsigned char> png = {
      0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44,
      0x52, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x02, 0x00, 0x00, 0x00, 0xfd,
      0xd4, 0x9a, 0x73, 0x00, 0x00, 0x00, 0x12, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0xf8,
      0xcf, 0xc0, 0xc0, 0x00, 0xc2, 0x0c, 0xff, 0x81, 0x00, 0x00, 0x1f, 0xee, 0x05, 0xfb, 0xf1,
      0xab, 0xba, 0x77, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
  return png;
}

/// The .mtl's map_Kd line number (1-based), for the tests of its warnings.
constexpr int OCTAHEDRON_MAP_KD_LINE = 5;

/// Writes <folder>/<stem>.obj, <stem>.mtl and (with_texture) tex.png; returns the OBJ's path.
inline std::string write_textured_octahedron(const std::string& folder, const std::string& stem,
                                             bool with_texture) {
  const std::filesystem::path dir(folder);
  std::ofstream(dir / (stem + ".mtl")) << "# made by tests/support/textured_octahedron.hpp\n"
                                          "newmtl skin\n"
                                          "Kd 0.8 0.2 0.1\n"
                                          "d 1.0\n"
                                          "map_Kd -o 0 0 0 -clamp off tex.png\n";
  std::ofstream obj(dir / (stem + ".obj"));
  obj << "mtllib " << stem << ".mtl\n"
      << "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
         "vt 0 0.5\nvt 1 0.5\nvt 0.5 0.75\nvt 0.5 0.25\nvt 0.25 1\nvt 0.75 0\n"
         "usemtl skin\n"
         "f 1/1 3/3 5/5\nf 3/3 2/2 5/5\nf 2/2 4/4 5/5\nf 4/4 1/1 5/5\n"
         "f 3/3 1/1 6/6\nf 2/2 3/3 6/6\nf 4/4 2/2 6/6\nf 1/1 4/4 6/6\n";
  if (with_texture) {
    const std::vector<unsigned char>& png = tiny_png();
    std::ofstream(dir / "tex.png", std::ios::binary)
        .write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  }
  return (dir / (stem + ".obj")).string();
}

}  // namespace shellcontract::test
