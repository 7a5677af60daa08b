#pragma once
// What the solver freezes for its anisotropic faces at the start of a solve (private to src/pbd,
// solver.cpp): each face's unit normal, for the paper's k_A term (math-spec 9.3), and, in the
// inversion-aware mode, its orientation s = sign(n . n_ref) (math-spec 4.2).

#include <cstddef>
#include <vector>

#include "pbd/constraint_batches.hpp"
#include "pbd/constraints.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract::aniso_frames {

inline Vec3 row(const Positions& x, int i) { return Vec3(x(i, 0), x(i, 1), x(i, 2)); }

/// normal[i] = the unit normal of face i at x, zero for a collapsed face (no inward push).
inline void face_normals(const std::vector<MembraneConstraint>& faces_a, const Positions& x,
                         std::vector<Vec3>& normal) {
  for (std::size_t i = 0; i < faces_a.size(); ++i) {
    const auto& v = faces_a[i].v;
    const Vec3 N = (row(x, v[0]) - row(x, v[2])).cross(row(x, v[1]) - row(x, v[2]));
    const double len = N.norm();
    normal[i] = len > 0.0 ? Vec3(N / len) : Vec3::Zero();
  }
}

/// orientation[i] = sign(normal[i] . n_ref), n_ref the normalized sum of the area-weighted vertex
/// normals (over `faces`, the mesh) of face i's corners; a tie counts as not inverted.
/// @param vertex_normal  scratch, #V by 3
inline void inversion_orientations(const std::vector<MembraneConstraint>& faces_a,
                                   const Faces& faces, const Positions& x,
                                   const std::vector<Vec3>& normal, Positions& vertex_normal,
                                   std::vector<double>& orientation) {
  vertex_normal.setZero(x.rows(), 3);
  for (Eigen::Index j = 0; j < faces.rows(); ++j) {
    const Vec3 N = (row(x, faces(j, 0)) - row(x, faces(j, 2)))
                       .cross(row(x, faces(j, 1)) - row(x, faces(j, 2)));
    for (int k = 0; k < 3; ++k) vertex_normal.row(faces(j, k)) += N.transpose();
  }
  for (std::size_t i = 0; i < faces_a.size(); ++i) {
    const auto& v = faces_a[i].v;
    Vec3 ref = Vec3::Zero();
    for (int k = 0; k < 3; ++k) {
      const Vec3 nv = row(vertex_normal, v[k]);
      const double len = nv.norm();
      if (len > 0.0) ref += nv / len;
    }
    // Tie (n . n_ref = 0, or no reference) counts as not inverted (math-spec 5 tie rule).
    orientation[i] = normal[i].dot(ref) < 0.0 ? -1.0 : 1.0;
  }
}

/// The coloured order's copy: face i's normal and orientation into its batch lane, lane[i] =
/// BATCH_LANES * batch + lane (faces without batches: lane is empty, nothing to write).
inline void write_into_batches(const std::vector<std::size_t>& lane,
                               const std::vector<Vec3>& normal,
                               const std::vector<double>& orientation,
                               ColouredBatches<AnisoBatch>& batches) {
  for (std::size_t i = 0; i < lane.size(); ++i) {
    AnisoBatch& b = batches.batches[lane[i] / BATCH_LANES];
    const std::size_t k = lane[i] % BATCH_LANES;
    for (int d = 0; d < 3; ++d) b.normal[d][k] = normal[i](d);
    b.orientation[k] = orientation[i];
  }
}

}  // namespace shellcontract::aniso_frames
