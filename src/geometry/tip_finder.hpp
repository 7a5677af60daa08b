// Private to the region finders: the tip finder, RegionMethod::Tips of select_spherical_regions
// (algorithm in tip_finder.cpp and docs/math/tip-finder.md).
#pragma once

#include <vector>

#include "shellcontract/mesh.hpp"
#include "shellcontract/regions.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract::detail {

/// The regions around the tips of protrusions: one entry per face, the region id or -1, ids by
/// decreasing area as select_spherical_regions; the report as there (seed_vertices = tips,
/// candidates = ends kept before the filters). Same preconditions (the caller checked the
/// options).
std::vector<int> select_tip_regions(const Mesh& mesh, const Positions& x,
                                    const RegionOptions& options, RegionReport* report);

}  // namespace shellcontract::detail
