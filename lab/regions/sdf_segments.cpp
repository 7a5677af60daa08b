// CGAL's shape-diameter-function segmentation (Surface_mesh_segmentation, Shapira et al. 2008)
// on one mesh: its time and one segment id per face (lab/regions/sdf.md). A lab check of whether
// CGAL already finds the parts of issue 55, point 1; not part of the product.
// Build: mkdir -p /tmp/sdf && g++ -O2 -DNDEBUG -std=c++17 lab/regions/sdf_segments.cpp \
//          -o /tmp/sdf/sdf -lgmp -lmpfr
// Usage: /tmp/sdf/sdf MESH [CLUSTERS=5] [SMOOTHING=0.26] [OUT=seg.txt] (sdf.md runs it per mesh
// with OUT=/tmp/sdf/NAME.seg, the layout sdf_iou.py reads)
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/mesh_segmentation.h>
#include <CGAL/Polygon_mesh_processing/IO/polygon_mesh_io.h>
#include <chrono>
#include <iostream>
#include <fstream>
typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Surface_mesh<K::Point_3> Mesh;
typedef Mesh::Face_index F;
int main(int argc, char** argv) {
  Mesh m; if (!CGAL::IO::read_polygon_mesh(argv[1], m)) return 1;
  int k = argc > 2 ? atoi(argv[2]) : 5; double lambda = argc > 3 ? atof(argv[3]) : 0.26;
  auto t0 = std::chrono::steady_clock::now();
  auto sdf = m.add_property_map<F, double>("f:sdf").first;
  CGAL::sdf_values(m, sdf);
  auto t1 = std::chrono::steady_clock::now();
  auto seg = m.add_property_map<F, std::size_t>("f:seg").first;
  std::size_t n = CGAL::segmentation_from_sdf_values(m, sdf, seg, k, lambda);
  auto t2 = std::chrono::steady_clock::now();
  std::cerr << "faces " << m.number_of_faces() << " segments " << n << " sdf "
            << std::chrono::duration<double>(t1 - t0).count() << " s, seg "
            << std::chrono::duration<double>(t2 - t1).count() << " s\n";
  std::ofstream o(argc > 4 ? argv[4] : "seg.txt");
  for (F f : m.faces()) o << seg[f] << "\n";
}
