// The one Mesh typedef (style.md section 3). Nothing else in the project names a CGAL kernel.
// Include this only in translation units that need CGAL: the physics kernels use Eigen only.
#pragma once

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

namespace shellcontract {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point3>;
using VertexIndex = Mesh::Vertex_index;
using FaceIndex = Mesh::Face_index;
using EdgeIndex = Mesh::Edge_index;
using HalfedgeIndex = Mesh::Halfedge_index;

}  // namespace shellcontract
