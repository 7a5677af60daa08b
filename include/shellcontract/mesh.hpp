// The one Mesh typedef: a CGAL Surface_mesh (house-style.md section 3); nothing else in the project
// names a CGAL kernel. Include this only in translation units that need CGAL: the physics kernels
// use Eigen only (shellcontract/types.hpp).
#pragma once

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include "shellcontract/types.hpp"

namespace shellcontract {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point3>;
using VertexIndex = Mesh::Vertex_index;
using FaceIndex = Mesh::Face_index;
using EdgeIndex = Mesh::Edge_index;
using HalfedgeIndex = Mesh::Halfedge_index;

/// Copies the mesh points into a Positions array (row i = vertex i).
/// @pre !mesh.has_garbage()
Positions positions_from_mesh(const Mesh& mesh);

}  // namespace shellcontract
