// Checks of an oriented point set before CGAL's Poisson reconstruction: the inputs on which the
// solve or the surface mesher crashed, never ended or wrapped a surface around a stray point are
// InputErrors naming the file and, where one point is to blame, its line.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "shellcontract/mesh.hpp"

namespace shellcontract {

using PointWithNormal = std::pair<Point3, Kernel::Vector_3>;

/// The point-set checks' messages: a number to 3 significant digits, a point as "(x, y, z)".
namespace point_text {
std::string text(double x);
std::string text(const Point3& p);
}  // namespace point_text

/// An oriented point set as read, with where each point came from.
struct OrientedPoints {
  std::string path;
  std::vector<PointWithNormal> points;
  std::vector<std::size_t> lines;  ///< each point's line in a text file; empty for a PLY

  /// "line 201" (text) or "vertex 12" (PLY, counted from 0 as in the file's vertex list).
  std::string where(std::size_t i) const;
};

/// The points to reconstruct from: each position once (its first line's normal), in the file's
/// order. Throws InputError naming the file (and the line) if there are fewer than 10 distinct
/// positions, a coordinate or normal length beyond what the solve's double arithmetic survives, one
/// position with normals that contradict each other, no volume (all in one plane), a spacing too
/// fine for the surface mesher, a point far from all the others, or points spanning far more than
/// their spacing. `neighbours`: how many nearest neighbours a point's spacing is measured over.
/// `kept`, if given, receives the index in `input.points` of each point returned.
std::vector<PointWithNormal> checked_points(const OrientedPoints& input, int neighbours,
                                            std::vector<std::size_t>* kept = nullptr);

}  // namespace shellcontract
