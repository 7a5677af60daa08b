// --delta auto (sim/contact_distance.hpp).
#include "sim/contact_distance.hpp"

#include <algorithm>

#include <CGAL/Polygon_mesh_processing/measure.h>

namespace shellcontract {

double mean_edge_length(const Mesh& mesh) {
  double sum = 0.0;
  std::size_t count = 0;
  for (const auto e : mesh.edges()) {
    sum += CGAL::Polygon_mesh_processing::edge_length(e, mesh);
    ++count;
  }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

double auto_contact_distance(const Mesh& mesh, double cap) {
  const double share = AUTO_DELTA_PER_MEAN_EDGE * mean_edge_length(mesh);
  // A mesh without edges, or with edges of length 0 only, gives a share of 0: the cap keeps the
  // contact distance positive (the collision step needs delta > 0).
  return share > 0.0 ? std::min(cap, share) : cap;
}

}  // namespace shellcontract
