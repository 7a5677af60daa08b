// Private to the region finders: the part finder, RegionMethod::Parts of
// select_spherical_regions (algorithm in part_finder.cpp and docs/math/part-finder.md).
#pragma once

#include <vector>

#include "geometry/curvature.hpp"
#include "shellcontract/mesh.hpp"
#include "shellcontract/regions.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract::detail {

std::vector<int> select_part_regions(const Mesh& mesh, const Positions& x, const RegionOptions& options,
                                     RegionReport* report, CurvatureField* curvature = nullptr);

}  // namespace shellcontract::detail
