// A textured sphere split at its UV seams, as Blender's PLY exporter and glTF importer split a
// mesh: one vertex per (position, texture coordinate) pair, so the longitude-0 seam has two copies
// of each of its vertices and each pole one copy per pole triangle, all at bitwise-identical
// positions. The triangles meet along the seam without sharing vertices: the mesh as given is
// open. Built from textured_uv_sphere (a closed mesh with per-corner UVs); the generator keeps,
// per split vertex, the closed mesh's vertex it copies, so that tests compare with that rather
// than with the code under test.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "support/textured_obj.hpp"

namespace shellcontract::test {

struct SeamSplitMesh {
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> x;  ///< per split vertex (copies share rows' values)
  std::vector<std::array<double, 2>> st;                          ///< per split vertex
  std::vector<std::array<std::size_t, 3>> tris;                   ///< on split vertices
  std::vector<std::size_t> closed_vertex;  ///< per split vertex: the closed sphere's vertex it copies
  std::size_t closed_vertices = 0;         ///< the closed sphere's vertex count

  /// An ascii PLY as Blender writes one (x y z, s t per vertex; float coordinates would round,
  /// so doubles: the copies stay bitwise equal either way), with a comment to keep.
  std::string ply() const {
    std::ostringstream o;
    o.precision(17);
    o << "ply\nformat ascii 1.0\ncomment seam-split sphere\nelement vertex " << x.rows()
      << "\nproperty double x\nproperty double y\nproperty double z\nproperty float s\nproperty float t\n"
      << "element face " << tris.size() << "\nproperty list uchar uint vertex_indices\nend_header\n";
    for (Eigen::Index i = 0; i < x.rows(); ++i)
      o << x(i, 0) << ' ' << x(i, 1) << ' ' << x(i, 2) << ' ' << st[static_cast<std::size_t>(i)][0] << ' '
        << st[static_cast<std::size_t>(i)][1] << '\n';
    for (const auto& t : tris) o << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    return o.str();
  }

  /// An OBJ of the same split vertices (`v` per split vertex, `vt` per vertex, `f v/vt`), with
  /// an object, a material and a comment to keep.
  std::string obj() const {
    std::ostringstream o;
    o.precision(17);
    o << "# seam-split sphere\nmtllib split.mtl\no split\n";
    for (Eigen::Index i = 0; i < x.rows(); ++i) o << "v " << x(i, 0) << ' ' << x(i, 1) << ' ' << x(i, 2) << '\n';
    for (const auto& uv : st) o << "vt " << uv[0] << ' ' << uv[1] << '\n';
    o << "usemtl skin\n";
    for (const auto& t : tris)
      o << "f " << t[0] + 1 << '/' << t[0] + 1 << ' ' << t[1] + 1 << '/' << t[1] + 1 << ' ' << t[2] + 1 << '/' << t[2] + 1 << '\n';
    return o.str();
  }
};

/// The textured sphere (nlat bands, nlon sectors) split at its seams; polygons fan-triangulated.
inline SeamSplitMesh seam_split_sphere(int nlat = 6, int nlon = 8) {
  const TexturedObj closed = textured_uv_sphere(nlat, nlon);
  SeamSplitMesh m;
  m.closed_vertices = static_cast<std::size_t>(closed.x.rows());
  std::map<std::pair<std::size_t, std::size_t>, std::size_t> split;  // (vertex, vt) -> split vertex
  std::vector<std::size_t> rows;
  const auto vertex = [&](const std::array<std::size_t, 2>& corner) {
    const auto [it, added] = split.emplace(std::make_pair(corner[0], corner[1]), rows.size());
    if (added) {
      rows.push_back(corner[0]);
      m.st.push_back(closed.uv[corner[1]]);
    }
    return it->second;
  };
  for (const auto& p : closed.polygons)
    for (std::size_t k = 1; k + 1 < p.size(); ++k) m.tris.push_back({vertex(p[0]), vertex(p[k]), vertex(p[k + 1])});
  m.closed_vertex = rows;
  m.x.resize(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t i = 0; i < rows.size(); ++i)
    m.x.row(static_cast<Eigen::Index>(i)) = closed.x.row(static_cast<Eigen::Index>(rows[i]));
  return m;
}

}  // namespace shellcontract::test
