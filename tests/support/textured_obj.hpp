// A textured OBJ made for the attribute tests: a latitude-longitude sphere of quads
// with triangle caps, UVs with a seam (the vertices of longitude 0 have u = 0 and u = 1) and one
// per pole triangle, one smooth normal per vertex, two groups with two materials, smoothing
// groups, comments and vertex colours on some `v` lines. The generator also returns what it
// wrote, so that tests compare with it rather than with the code under test.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

namespace shellcontract::test {

struct TexturedObj {
  std::string text;
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> x;  ///< the `v` positions
  std::vector<std::array<double, 2>> uv;                          ///< the `vt` values
  /// Per polygon (file order): its corners' vertex and vt indices (0-based).
  std::vector<std::vector<std::array<std::size_t, 2>>> polygons;
};

/// nlat >= 3 bands of latitude, nlon >= 3 of longitude, radius 1.
inline TexturedObj textured_uv_sphere(int nlat = 8, int nlon = 12) {
  TexturedObj t;
  const double pi = std::acos(-1.0);
  const int rings = nlat - 1;
  const std::size_t nv = 2 + static_cast<std::size_t>(rings * nlon);
  t.x.resize(static_cast<Eigen::Index>(nv), 3);
  t.x.row(0) << 0.0, 0.0, 1.0;
  auto ring_vertex = [&](int i, int j) { return static_cast<std::size_t>(1 + i * nlon + (j % nlon)); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < nlon; ++j) {
      const double th = pi * (i + 1) / nlat, ph = 2.0 * pi * j / nlon;
      t.x.row(static_cast<Eigen::Index>(ring_vertex(i, j))) << std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th);
    }
  const std::size_t south = nv - 1;
  t.x.row(static_cast<Eigen::Index>(south)) << 0.0, 0.0, -1.0;
  // vt: a (nlon + 1) x rings grid (u = 1 repeats u = 0: the seam), then one per pole triangle.
  auto grid_uv = [&](int i, int j) { return static_cast<std::size_t>(i * (nlon + 1) + j); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j <= nlon; ++j) t.uv.push_back({static_cast<double>(j) / nlon, 1.0 - static_cast<double>(i + 1) / nlat});
  const std::size_t north_uv = t.uv.size();
  for (int j = 0; j < nlon; ++j) t.uv.push_back({(j + 0.5) / nlon, 1.0});
  const std::size_t south_uv = t.uv.size();
  for (int j = 0; j < nlon; ++j) t.uv.push_back({(j + 0.5) / nlon, 0.0});

  for (int j = 0; j < nlon; ++j)  // north cap, counter-clockwise seen from outside
    t.polygons.push_back({{0, north_uv + static_cast<std::size_t>(j)}, {ring_vertex(0, j), grid_uv(0, j)}, {ring_vertex(0, j + 1), grid_uv(0, j + 1)}});
  for (int i = 0; i + 1 < rings; ++i)
    for (int j = 0; j < nlon; ++j)
      t.polygons.push_back({{ring_vertex(i, j), grid_uv(i, j)}, {ring_vertex(i + 1, j), grid_uv(i + 1, j)},
                            {ring_vertex(i + 1, j + 1), grid_uv(i + 1, j + 1)}, {ring_vertex(i, j + 1), grid_uv(i, j + 1)}});
  for (int j = 0; j < nlon; ++j)  // south cap
    t.polygons.push_back({{south, south_uv + static_cast<std::size_t>(j)}, {ring_vertex(rings - 1, j + 1), grid_uv(rings - 1, j + 1)},
                          {ring_vertex(rings - 1, j), grid_uv(rings - 1, j)}});

  std::ostringstream o;
  o.precision(17);
  o << "# textured sphere for the attribute tests\nmtllib sphere.mtl\no ball\n";
  for (std::size_t i = 0; i < nv; ++i) {
    o << "v " << t.x(static_cast<Eigen::Index>(i), 0) << ' ' << t.x(static_cast<Eigen::Index>(i), 1) << ' '
      << t.x(static_cast<Eigen::Index>(i), 2);
    if (i % 5 == 0) o << " 0.25 0.5 1";  // a vertex colour (an OBJ extension) to keep
    o << '\n';
  }
  for (const auto& uv : t.uv) o << "vt " << uv[0] << ' ' << uv[1] << '\n';
  for (std::size_t i = 0; i < nv; ++i)  // on the unit sphere the normal is the position
    o << "vn " << t.x(static_cast<Eigen::Index>(i), 0) << ' ' << t.x(static_cast<Eigen::Index>(i), 1) << ' '
      << t.x(static_cast<Eigen::Index>(i), 2) << '\n';
  const std::size_t half = t.polygons.size() / 2;
  for (std::size_t p = 0; p < t.polygons.size(); ++p) {
    if (p == 0) o << "g upper\nusemtl north\ns 1\n";
    if (p == half) o << "g lower\nusemtl south\ns off\n";
    o << 'f';
    for (const auto& [v, vt] : t.polygons[p]) o << ' ' << v + 1 << '/' << vt + 1 << '/' << v + 1;
    o << '\n';
  }
  t.text = o.str();
  return t;
}

}  // namespace shellcontract::test
