// Unit-diagonal normalization (math-spec 1.2). Eigen only.
#pragma once

#include "shellcontract/types.hpp"

namespace shellcontract {

/// x_normalized = (x - center) / scale, with center the bounding-box centre and scale its
/// diagonal, so the normalized mesh has bounding-box diagonal 1.
struct Normalization {
  Vec3 center = Vec3::Zero();
  double scale = 1.0;
};

/// |hi - lo|, a bounding box's diagonal: Eigen's norm() where its squares are exact enough, and
/// stableNorm() where they overflow or fall into the subnormals (a mesh at 1e160 or 1e-300 was
/// refused for a span it has). The same bits as norm() for every other box.
double bounding_diagonal(const Vec3& lo, const Vec3& hi);

/// @throws InputError if the bounding box has zero diagonal or non-finite coordinates
Normalization compute_normalization(const Positions& x);

/// Maps input-unit positions to normalized ones.
Positions normalize(const Positions& x, const Normalization& n);

/// Maps normalized positions back to input units.
Positions denormalize(const Positions& x, const Normalization& n);

/// denormalize into `out`, which is resized only if its shape differs from x's: into storage
/// taken beforehand it allocates nothing (run_contraction's result after a run that used all
/// the memory there is). The same bits as denormalize.
void denormalize_into(const Positions& x, const Normalization& n, Positions& out);

}  // namespace shellcontract
