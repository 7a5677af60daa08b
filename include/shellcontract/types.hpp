// Scalar and small fixed-size matrix types used by every physics kernel.
// Scalars are double everywhere (house-style.md section 4); nothing here sees CGAL.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

// The library and its users must allocate and free Eigen's dynamic matrices alike: the API hands
// them across (Positions, export.hpp). The ShellContract::shellcontract target (and every in-tree
// target) compiles with EIGEN_MAX_ALIGN_BYTES=64, which gives one allocator whatever the vector
// ISA (-mavx2, -march=native), EIGEN_DONT_VECTORIZE or AddressSanitizer (CMakeLists.txt,
// docs/architecture.md). A translation unit that would get another allocator (it lacks the
// definition and is not compiled for AVX-512, which gives the same) stops here: it would free or
// resize the library's matrices with the wrong one.
#if EIGEN_DEFAULT_ALIGN_BYTES != 64 || EIGEN_MALLOC_ALREADY_ALIGNED
#error "ShellContract: define EIGEN_MAX_ALIGN_BYTES=64 (ShellContract::shellcontract does)"
#endif

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
