// Read-only CGAL point property map over a contiguous Eigen position array, so that CGAL
// algorithms (PMP::volume, self_intersections, IO writers) read the simulation state without a
// mesh copy (the pattern of CGAL's measure.h with parameters::vertex_point_map).
#pragma once

#include <boost/property_map/property_map.hpp>

#include "shellcontract/mesh.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// Maps a vertex to the Point3 stored in row v.idx() of a Positions array.
/// The array must outlive the map and have one row per vertex of a garbage-free mesh.
class EigenPointMap {
 public:
  using key_type = VertexIndex;
  using value_type = Point3;
  using reference = Point3;  // returned by value: the array holds doubles, not Point3
  using category = boost::readable_property_map_tag;

  explicit EigenPointMap(const Positions& x) : x_(&x) {}
  /// Unbound map: CGAL default-constructs property maps in some algorithms (e.g. the Hausdorff
  /// distance) before assigning them; get() on an unbound map is not allowed.
  EigenPointMap() = default;

  friend Point3 get(const EigenPointMap& m, VertexIndex v) {
    const auto row = m.x_->row(static_cast<Eigen::Index>(v.idx()));
    return Point3(row(0), row(1), row(2));
  }

 private:
  const Positions* x_ = nullptr;
};

}  // namespace shellcontract
