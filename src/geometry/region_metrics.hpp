// Measures of a region (a set of faces): its area, perimeter and compactness, and the overlap of
// two face sets. Used by the region finder's filters, its tests and the lab's labelled set.
#pragma once

#include <vector>

#include "shellcontract/mesh.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// Area and boundary length of a set of faces at positions x.
struct RegionShape {
  double area = 0.0;         ///< sum of the face areas, length^2
  double perimeter = 0.0;    ///< total length of the edges with exactly one side in the set
                             ///< (outer boundary and holes; a mesh border edge counts too)
  double compactness = 0.0;  ///< perimeter^2 / (4 pi area): 1 for a flat disc, larger for any
                             ///< other shape; +inf for zero area
};

/// @param in_region one flag per face (index = face index), nonzero = in the set.
/// @pre  in_region.size() == number_of_faces, x.rows() == number_of_vertices.
/// @throws UsageError on a size mismatch.
RegionShape region_shape(const Mesh& mesh, const Positions& x, const std::vector<char>& in_region);

/// Intersection over union of two face sets given as flags per face (by face count, so only
/// meaningful on one mesh; 1 when both are empty).
/// @throws UsageError if the sizes differ.
double face_set_iou(const std::vector<char>& a, const std::vector<char>& b);

}  // namespace shellcontract
