// Private to the region finder: the cotangent Laplacian of a triangle mesh, built straight into
// compressed columns in parallel (lab/regions/speed.md, "branch speed5"). Its entries are the
// bits Eigen's setFromTriplets gives for the finder's triplet list, so the smoothed curvature
// and everything after it do not change.
#pragma once

#include <array>
#include <vector>

#include <Eigen/SparseCore>

#include "shellcontract/types.hpp"

namespace shellcontract::detail {

/// L with L(i, j) = -sum w and L(i, i) = sum w over the half-edges (i, j) of tri, w = cot(angle
/// at o) / 2 for the face (i, j, o) and no weight at a degenerate corner (cross product at most
/// 1e-14 |a| |b|); positive semidefinite, both triangles stored. Equal, bit for bit and entry
/// for entry (explicit zeros included), to setFromTriplets on the triplets, per face and k = 0,
/// 1, 2 with i = t[k], j = t[k + 1], o = t[k + 2]: (i, j, -w), (j, i, -w), (i, i, w), (j, j, w).
/// Each entry sums its contributions in that list order, whatever the threads.
Eigen::SparseMatrix<double> cotan_laplacian(const std::vector<std::array<int, 3>>& tri, const Positions& x);

}  // namespace shellcontract::detail
