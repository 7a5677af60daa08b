// An oriented point set for the reconstruct tests: a unit sphere sampled on a Fibonacci spiral.
#pragma once

#include <cmath>
#include <fstream>
#include <string>

namespace shellcontract::test {

/// Writes n points of the unit sphere with their outward normals, "x y z nx ny nz" per line.
inline void write_sphere_xyz(const std::string& path, int n = 3000) {
  std::ofstream out(path);
  out.precision(17);
  const double golden = 3.14159265358979323846 * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z), t = golden * i;
    const double x = r * std::cos(t), y = r * std::sin(t);
    out << x << ' ' << y << ' ' << z << ' ' << x << ' ' << y << ' ' << z << '\n';
  }
}

}  // namespace shellcontract::test
