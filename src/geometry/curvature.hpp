// Discrete per-vertex curvature of a triangle mesh on a given position array (house-style.md section 3:
// CGAL 5.5 has no interpolated_corrected_curvatures, so we compute it ourselves).
//
// Conventions (libigl's gaussian_curvature / cotmatrix / massmatrix(MIXED) give the same numbers
// up to the sign and factor noted here):
//   - Mixed area A_i (Meyer, Desbrun, Schroeder, Barr 2003, "Discrete differential-geometry
//     operators for triangulated 2-manifolds", section 3.3 / Fig. 4): Voronoi area for
//     non-obtuse triangles, area/2 for the obtuse corner and area/4 for the other corners of an
//     obtuse triangle. The mixed areas tile the surface: sum_i A_i = total area.
//   - Angle deficit d_i = 2 pi - sum of the triangle angles at vertex i (radians). For a closed
//     mesh sum_i d_i = 2 pi chi (discrete Gauss-Bonnet, exact up to rounding).
//   - Gaussian curvature K_i = d_i / A_i (1/length^2). Sphere of radius r: K = 1/r^2.
//   - Mean curvature H_i = (k1 + k2) / 2 (1/length), from the cotangent mean-curvature normal
//       Hn_i = 1/(4 A_i) sum_j (cot alpha_ij + cot beta_ij) (x_i - x_j)      (Meyer eq. 8 / 2)
//     projected on the unit area-weighted vertex normal n_i: H_i = Hn_i . n_i.
//     \note SIGN: with outward-oriented faces (counter-clockwise seen from outside, what
//     read_input_mesh produces) H > 0 on a convex surface: a sphere of radius r gives H = +1/r,
//     a dent gives H < 0. This is the opposite of libigl's cotmatrix sign (its L is negative
//     semi-definite) and half of the "mean curvature" 2H that some libraries report.
//   - Principal curvatures k_max/k_min = H +- sqrt(max(H^2 - K, 0)): the discrete H and K are
//     estimated separately, so H^2 - K can come out slightly negative near umbilics; it is
//     clamped to 0 there (the vertex is then reported as exactly umbilic).
#pragma once

#include <Eigen/Core>

#include "shellcontract/mesh.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// Per-vertex curvature quantities; every vector has one entry per vertex, row = v.idx().
struct CurvatureField {
  Eigen::VectorXd mixed_area;     ///< A_i, length^2 (0 only if every incident face is degenerate)
  Eigen::VectorXd angle_deficit;  ///< d_i = 2 pi - sum of incident angles, radians
  Eigen::VectorXd gaussian;       ///< K_i = d_i / A_i, 1/length^2 (0 where A_i = 0)
  Eigen::VectorXd mean;           ///< H_i, 1/length, > 0 on a convex outward-oriented surface
  Eigen::VectorXd k_max;          ///< larger principal curvature H + sqrt(max(H^2 - K, 0))
  Eigen::VectorXd k_min;          ///< smaller principal curvature H - sqrt(max(H^2 - K, 0))
  /// Unit area-weighted vertex normals (#V by 3), outward for an outward-oriented mesh; zero
  /// rows where all incident faces are degenerate.
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> normal;
};

/// Computes mixed areas, angle deficits, Gaussian, mean and principal curvatures of the
/// triangle mesh `mesh` at positions `x` (so the same mesh serves the rest and deformed states).
///
/// Degenerate input is guarded, not refused: a triangle with (numerically) zero area adds no
/// cotangent weight and no area; its angles still sum to pi (a zero-length edge gives pi/2 at
/// its two ends and 0 opposite; three coincident points give pi/3 each), so Gauss-Bonnet holds
/// for every closed mesh. A vertex with zero mixed area gets H = K = 0.
///
/// @param mesh triangle mesh (connectivity only is used).
/// @param x    vertex positions, #V by 3, row i = vertex i, any length unit (any scale a double
///             holds: see detail::finder_exponent).
/// @pre  mesh is a pure triangle mesh without garbage (!mesh.has_garbage()), x.rows() ==
///       number_of_vertices. Boundary vertices are allowed, but their deficit is 2 pi minus the
///       angle sum (not the geodesic-curvature form), so K there is not meaningful.
/// @return the per-vertex field (units: those of x).
/// @throws UsageError if the preconditions on size, garbage or face degree fail.
CurvatureField compute_curvature(const Mesh& mesh, const Positions& x);

namespace detail {
/// 0 when the largest side of x's bounding box is in [2^-65, 2^64), else the exponent k that
/// brings it to [0.5, 1) in x * 2^-k. compute_curvature and the region finders work on x * 2^-k
/// then, exactly (a power of two), where their squares of lengths neither over- nor underflow:
/// at 1e100 the curvature was NaN and the finders found no region.
int finder_exponent(const Positions& x);
/// The field of x * 2^-k as the field of x: areas times 2^2k, curvatures times 2^-k or 2^-2k.
void unscale_curvature(int k, CurvatureField& c);
}  // namespace detail

/// Writes field.mean into the vertex map "v:mean_curvature" and field.gaussian into
/// "v:gaussian_curvature" (property.hpp names), creating the maps if they are not attached and
/// overwriting them if they are (so a deformed state can be stored after the rest state).
/// @param mesh  mesh the field was computed on.
/// @param field result of compute_curvature on this mesh (sizes = number_of_vertices).
/// @throws UsageError if the sizes do not match.
void store_curvature(Mesh& mesh, const CurvatureField& field);

}  // namespace shellcontract
