// Unit-diagonal normalization (design.md "Units and scale", math-spec 1.2). Eigen only.
#pragma once

#include "shellcontract/types.hpp"

namespace shellcontract {

/// x_normalized = (x - center) / scale, with center the bounding-box centre and scale its
/// diagonal, so the normalized mesh has bounding-box diagonal 1.
struct Normalization {
  Vec3 center = Vec3::Zero();
  double scale = 1.0;
};

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
