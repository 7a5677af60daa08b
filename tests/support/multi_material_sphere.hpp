// A small closed OBJ whose faces use several materials, for the glTF's primitives (one per
// material) in the export tests and the validator's sample: a UV sphere with one texture
// coordinate per vertex (no seam), its faces under `body`, `eyes` and `teeth` (body and teeth name
// the same PNG), `ghost` (defined in no library) and, for the first few, no usemtl at all. The
// materials alternate around the sphere, so that a primitive's faces are not one run of the file.
#pragma once

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "support/textured_octahedron.hpp"

namespace shellcontract::test {

/// The .mtl's materials as written by write_multi_material_sphere (Kd, alpha, whether map_Kd).
struct SphereMaterial {
  const char* name;
  double r, g, b, alpha;
  bool textured;
};
inline const std::vector<SphereMaterial>& sphere_materials() {
  static const std::vector<SphereMaterial> m = {{"body", 0.8, 0.6, 0.5, 1.0, true},
                                                {"eyes", 0.1, 0.2, 0.9, 0.5, false},
                                                {"teeth", 1.0, 1.0, 1.0, 1.0, true}};
  return m;
}

/// Writes <folder>/<stem>.obj, <stem>.mtl and skin.png; returns the OBJ's path.
inline std::string write_multi_material_sphere(const std::string& folder, const std::string& stem) {
  const std::filesystem::path dir(folder);
  {
    std::ofstream mtl(dir / (stem + ".mtl"));
    mtl << "# made by tests/support/multi_material_sphere.hpp\n";
    for (const SphereMaterial& m : sphere_materials()) {
      mtl << "newmtl " << m.name << "\nKd " << m.r << ' ' << m.g << ' ' << m.b << '\n';
      if (m.alpha < 1.0) mtl << "d " << m.alpha << '\n';
      if (m.textured) mtl << "map_Kd skin.png\n";
    }
  }
  const std::vector<unsigned char>& png = tiny_png();
  std::ofstream(dir / "skin.png", std::ios::binary)
      .write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));

  constexpr int rings = 8, sectors = 12;  // rings - 1 circles of vertices between the poles
  const double pi = std::acos(-1.0);
  std::vector<std::array<double, 3>> v{{0.0, 0.0, 1.0}};
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const double t = pi * i / rings, p = 2.0 * pi * j / sectors;
      v.push_back({std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)});
    }
  v.push_back({0.0, 0.0, -1.0});
  const int bottom = static_cast<int>(v.size()) - 1;
  auto at = [&](int i, int j) { return 1 + (i - 1) * sectors + j % sectors; };  // circle i >= 1
  std::vector<std::array<int, 3>> f;  // counter-clockwise seen from outside
  for (int j = 0; j < sectors; ++j) f.push_back({0, at(1, j), at(1, j + 1)});
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      f.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      f.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  for (int j = 0; j < sectors; ++j) f.push_back({bottom, at(rings - 1, j + 1), at(rings - 1, j)});

  std::ofstream obj(dir / (stem + ".obj"));
  obj.precision(17);
  obj << "mtllib " << stem << ".mtl\n";
  for (const auto& p : v) obj << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& p : v) obj << "vt " << 0.5 + 0.5 * p[0] << ' ' << 0.5 + 0.5 * p[1] << '\n';
  std::string current;
  for (std::size_t k = 0; k < f.size(); ++k) {
    double x = 0.0, z = 0.0;
    for (const int i : f[k]) {
      x += v[static_cast<std::size_t>(i)][0] / 3.0;
      z += v[static_cast<std::size_t>(i)][2] / 3.0;
    }
    const std::string m = k < 5 ? "" : z > 0.55 ? "eyes" : z < -0.55 ? "teeth" : x > 0.4 ? "ghost" : "body";
    if (m != current) obj << "usemtl " << m << '\n';
    current = m;
    obj << 'f';
    for (const int i : f[k]) obj << ' ' << i + 1 << '/' << i + 1;
    obj << '\n';
  }
  return (dir / (stem + ".obj")).string();
}

}  // namespace shellcontract::test
