// The two cheap culls of the collision step's filter stage, four stencils at a time: the swept
// box test (swept_boxes_apart) and Tang et al.'s non-penetration filter
// (nonpenetration_filter_culls with FilterBound::Coarse, math-spec 10.4: its rounding bound
// costs a fifth of the tight one's arithmetic, and with the collision step's tolerance it culls
// the same pairs on bear); and, on request, the axes half of the narrow phase's separating-axis
// cull (separating_axes_culls), which settles most of the pairs the two keep on finer meshes.
// Each lane performs the scalar functions' floating-point operations in the same order, so every
// answer is the scalar answer, bit for bit; only the work is shared. AVX2 when the CPU has it
// (checked at run time), else the scalar functions.
#pragma once

#include <array>
#include <cstdint>

#include "collision/ccd.hpp"

namespace shellcontract {

/// Stencils per cull_batch call.
static constexpr int CULL_LANES = 4;

/// Which code cull_batch runs (Auto: AVX2 if the CPU has it).
enum class CullIsa { Auto, Scalar };

/// For k < count (1..CULL_LANES): culled[k] = swept_boxes_apart(kind, s0, s1, tolerance) ||
/// nonpenetration_filter_culls(kind, s0, s1, tolerance, FilterBound::Coarse), where s0 and s1
/// are the stencil of vertex ids v[k] (ccd.hpp order) at the start and end positions; and, if
/// `axes` is given, axes[k] = separating_axes_culls(kind, s0, s1, tolerance), the first half of
/// the narrow phase's separating-axis cull, from the same loaded positions.
/// @param x0, x1  #V by 3 positions, row-major (Positions::data())
/// @param v       count vertex-id stencils, all of primitive kind `kind`
void cull_batch(CcdPrimitive kind, const double* x0, const double* x1,
                const std::array<int, 4>* v, int count, double tolerance, std::uint8_t* culled,
                CullIsa isa = CullIsa::Auto, std::uint8_t* axes = nullptr);

/// True if cull_batch's Auto runs the AVX2 code on this CPU.
bool cull_batch_avx2_available();

}  // namespace shellcontract
