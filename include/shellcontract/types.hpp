// Scalar and small fixed-size matrix types used by every physics kernel.
// Scalars are double everywhere (style.md section 4); nothing here sees CGAL.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

namespace shellcontract {

using Scalar = double;
using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;
/// 3x2 deformation gradient / PK1 of a triangle (columns are the two rest-frame directions).
using Mat32 = Eigen::Matrix<double, 3, 2>;
/// 2x3 projection onto the current triangle plane (math-spec 4.2, the paper's p).
using Mat23 = Eigen::Matrix<double, 2, 3>;
using Vec9 = Eigen::Matrix<double, 9, 1>;
using Vec12 = Eigen::Matrix<double, 12, 1>;

/// Vertex positions, one row per vertex, indexed by the mesh vertex index (#V by 3).
using Positions = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// Triangle vertex ids, one row per face, counter-clockwise seen from outside (#F by 3).
using Faces = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

}  // namespace shellcontract
