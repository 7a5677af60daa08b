// Private to the region finders: the tip finder, RegionMethod::Tips of select_spherical_regions
// (algorithm in tip_finder.cpp and docs/math/tip-finder.md).
#pragma once

#include <vector>

#include "geometry/curvature.hpp"
#include "shellcontract/mesh.hpp"
#include "shellcontract/regions.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract::detail {

/// The regions around the tips of protrusions: one entry per face, the region id or -1, ids by
/// decreasing area as select_spherical_regions; the report as there (seed_vertices = tips,
/// candidates = ends kept before the filters). Same preconditions (the caller checked the
/// options). When curvature is not null it receives the curvature field computed on the way
/// (mark_spherical_regions stores it for the PLY instead of computing it again).
std::vector<int> select_tip_regions(const Mesh& mesh, const Positions& x, const RegionOptions& options,
                                    RegionReport* report, CurvatureField* curvature = nullptr);

}  // namespace shellcontract::detail
