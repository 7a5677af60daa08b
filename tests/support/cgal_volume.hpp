// Volumes measured with CGAL's PMP::volume on the positions a run wrote: an instrument that is
// not the code under test (the run's V/V0 comes from the simulator's own volume), for the
// target-volume tests.
#pragma once

#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>

#include <stdexcept>
#include <string>

#include "shellcontract/mesh.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract::test {

/// PMP::volume of a closed, outward-oriented mesh.
inline double cgal_volume(const Mesh& m) {
  return CGAL::to_double(CGAL::Polygon_mesh_processing::volume(m));
}

/// The volume of `input`'s connectivity at positions x (row i = vertex of index i) over the
/// input's own volume.
inline double cgal_volume_ratio(const Mesh& input, const Positions& x) {
  if (static_cast<std::size_t>(x.rows()) != input.number_of_vertices())
    throw std::invalid_argument("cgal_volume_ratio: positions do not match the mesh");
  Mesh out = input;
  for (const VertexIndex v : out.vertices()) {
    const Eigen::Index i = static_cast<Eigen::Index>(v.idx());
    out.point(v) = Point3(x(i, 0), x(i, 1), x(i, 2));
  }
  return cgal_volume(out) / cgal_volume(input);
}

/// A mesh file read with CGAL's own reader (not the project's), for measuring what a run wrote.
inline Mesh cgal_read(const std::string& path) {
  Mesh m;
  if (!CGAL::IO::read_polygon_mesh(path, m) || m.is_empty())
    throw std::runtime_error("CGAL could not read " + path);
  return m;
}

/// The positions of a mesh file read with CGAL's reader (cgal_read), row i = vertex i.
inline Positions cgal_read_positions(const std::string& path) {
  const Mesh m = cgal_read(path);
  Positions x(static_cast<Eigen::Index>(m.number_of_vertices()), 3);
  for (const VertexIndex v : m.vertices()) {
    const Point3& p = m.point(v);
    x.row(static_cast<Eigen::Index>(v.idx())) << p.x(), p.y(), p.z();
  }
  return x;
}

}  // namespace shellcontract::test
