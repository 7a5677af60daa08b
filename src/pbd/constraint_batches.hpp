// Batched projections for the Coloured order (math-spec 9.4): four constraints of ONE colour
// projected together, one per SIMD lane. Constraints of a colour share no vertex, so the four
// lanes are independent and a batch gives the same result as projecting its four constraints one
// after the other with the same arithmetic. The rest data is stored structure-of-arrays per batch
// (flat per-colour arrays, no pointers) so that a sweep streams through memory. The state is
// read from and written to PaddedVertex rows (x, y, z, w): one aligned 256-bit load or store per
// vertex instead of a 2 + 1 split and a separate inverse-mass gather.
//
// Two implementations, chosen once per process:
//  - AVX2 + FMA (x86-64 CPUs that have both; function-level target attribute, so the default
//    build still runs on any x86-64): four lanes in one 256-bit register. The compiler fuses
//    multiply-adds, so results may differ from the scalar kernels in the last bits (tested to
//    1e-12 relative), but they are deterministic and independent of the thread count.
//  - scalar: the kernels of constraint_kernels.hpp lane by lane (bit-identical to them).
#pragma once

#include <array>
#include <cstddef>
#include <type_traits>
#include <vector>

#include "material/active_fiber.hpp"
#include "material/anisotropic_arap.hpp"
#include "material/anisotropic_sqrt.hpp"
#include "material/anisotropic_stvk.hpp"
#include "material/corotated.hpp"
#include "material/linear.hpp"
#include "material/mooney_rivlin.hpp"
#include "material/stvk.hpp"
#include "pbd/constraint_kernels.hpp"
#include "pbd/constraints.hpp"

namespace shellcontract {

/// Constraints per batch: one 256-bit register of doubles.
inline constexpr int BATCH_LANES = 4;

/// One vertex of the batched kernels' state: position and inverse mass, one 32-byte row.
struct alignas(32) PaddedVertex {
  double x, y, z;  ///< position (normalized units)
  double w;        ///< inverse mass (0 = pinned)
};

/// Copies vertices [begin, end) of positions x (3 per vertex) and inverse masses w into xw.
void pack_padded(const double* x, const double* w, std::size_t begin, std::size_t end, PaddedVertex* xw);

/// Copies the positions of vertices [begin, end) of xw back to x (3 per vertex).
void unpack_padded(const PaddedVertex* xw, std::size_t begin, std::size_t end, double* x);

/// pack_padded with the rows in another order: row k of xw [begin, end) gets vertex row_vertex[k]
/// of x and w (the solver keeps its rows in breadth-first order, see solver.cpp).
void pack_padded(const double* x, const double* w, const int* row_vertex, std::size_t begin,
                 std::size_t end, PaddedVertex* xw);

/// unpack_padded with the rows in another order: row k of xw [begin, end) goes back to vertex
/// row_vertex[k] of x.
void unpack_padded(const PaddedVertex* xw, const int* row_vertex, std::size_t begin,
                   std::size_t end, double* x);

/// Four membrane constraints of one colour (PackedMembrane fields, lane k = k-th constraint).
/// Lanes at or past `count` are padding: copies of lane 0 (its vertex ids, so every read stays in
/// bounds and on this thread's vertices, and its rest data, so every lane's arithmetic is finite);
/// their positions are never written (an XPBD multiplier of their own may be).
struct alignas(32) MembraneBatch {
  double dm00[BATCH_LANES], dm01[BATCH_LANES], dm11[BATCH_LANES];  ///< Dm^-1 (math-spec 4.1)
  double rest_area[BATCH_LANES];                                   ///< Abar
  double max_step[BATCH_LANES];                                    ///< clamp (math-spec 9.1d)
  int v[3][BATCH_LANES];  ///< v[j][k]: vertex j of lane k
  int count;              ///< real lanes, 1..4
  int same_colour_next;   ///< 1 when batch + 1 is of the same colour (shares no vertex with this
                          ///< one: the StVK AVX2 kernel then projects the two together)
};

/// Four isometric hinges of one colour (IsometricHingeConstraint fields, stencil order of
/// bending/hinge.hpp). Padding lanes as in MembraneBatch.
struct alignas(32) IsometricBatch {
  double K[4][BATCH_LANES];            ///< K[j][k]: rest cotangent weight j of lane k (math-spec 8.1)
  double three_over_area[BATCH_LANES]; ///< 3 / (A0 + A1)
  double max_step[BATCH_LANES];        ///< clamp (math-spec 9.1d)
  int v[4][BATCH_LANES];
  int count;
};

/// Four dihedral hinges of one colour (DihedralHingeConstraint fields, stencil order of
/// bending/hinge.hpp). Padding lanes as in MembraneBatch.
struct alignas(32) DihedralBatch {
  double rest_angle[BATCH_LANES];  ///< theta_bar (math-spec 8.3)
  double kappa[BATCH_LANES];       ///< kappa_bar; 0 for an inactive hinge
  double max_step[BATCH_LANES];    ///< clamp (math-spec 9.1d)
  int v[4][BATCH_LANES];
  int count;
  int same_colour_next;  ///< 1 when batch + 1 is of the same colour (the AVX2 kernel then
                         ///< projects the two together)
};

/// Four anisotropic (E_A) faces of one colour (math-spec 7, 9.3): MembraneBatch's rest data, the
/// fibre and k_A, and the orientation s and unit normal n the solver freezes for each solve.
/// Padding lanes as in MembraneBatch.
struct alignas(32) AnisoBatch {
  double dm00[BATCH_LANES], dm01[BATCH_LANES], dm11[BATCH_LANES];  ///< Dm^-1 (math-spec 4.1)
  double rest_area[BATCH_LANES];                                   ///< Abar
  double max_step[BATCH_LANES];                                    ///< clamp (math-spec 9.1d)
  double fiber[2][BATCH_LANES];        ///< unit fibre a in the rest frame (ElementMaterialData)
  double k_a[BATCH_LANES];             ///< k_A of the paper's inward term (math-spec 9.3)
  double orientation[BATCH_LANES];     ///< s (math-spec 4.2), set per solve
  double normal[3][BATCH_LANES];       ///< frozen unit outward normal n, set per solve
  int v[3][BATCH_LANES];
  int count;
};

/// Batches of one constraint kind grouped by colour: colour c owns batches
/// [offsets[c], offsets[c + 1]); each colour's constraints fill its batches in order, so only a
/// colour's last batch can have padding lanes.
template <class Batch>
struct ColouredBatches {
  std::vector<Batch> batches;
  std::vector<std::size_t> offsets{0};  ///< size #colours + 1, in batches

  int num_colours() const { return static_cast<int>(offsets.size()) - 1; }
};

/// Packs membranes already grouped by colour (colour c at [colour_offsets[c],
/// colour_offsets[c + 1]) of `records`) into batches, in the same order.
ColouredBatches<MembraneBatch> make_membrane_batches(const std::vector<PackedMembrane>& records,
                                                     const std::vector<std::size_t>& colour_offsets);

/// Packs isometric hinges grouped by colour (see make_membrane_batches).
ColouredBatches<IsometricBatch> make_isometric_batches(
    const std::vector<IsometricHingeConstraint>& records,
    const std::vector<std::size_t>& colour_offsets);

/// Packs dihedral hinges grouped by colour (see make_membrane_batches).
ColouredBatches<DihedralBatch> make_dihedral_batches(
    const std::vector<DihedralHingeConstraint>& records,
    const std::vector<std::size_t>& colour_offsets);

/// Packs anisotropic faces grouped by colour (see make_membrane_batches) with their fibres
/// (data[i] of records[i]) and k_A; orientation 1 and normal 0 until the solver sets them.
ColouredBatches<AnisoBatch> make_aniso_batches(const std::vector<PackedMembrane>& records,
                                               const std::vector<ElementMaterialData>& data,
                                               const std::vector<double>& k_a,
                                               const std::vector<std::size_t>& colour_offsets);

/// Which implementation a batch projection runs.
enum class BatchIsa {
  Auto,    ///< AVX2 + FMA when the CPU has both, else Scalar
  Scalar,  ///< the scalar kernels lane by lane
};

/// True when BatchIsa::Auto runs the AVX2 + FMA code on this CPU.
bool batch_avx2_available();

/// Projects `count` membrane batches (StVK, C-form of math-spec 4.4) in order: PBD with the
/// guards of math-spec 9.1(d) when lambda == nullptr, else XPBD (9.2) with one multiplier per
/// lane at lambda[4 b + k] for batch b. Same contract per lane as project_membrane with
/// stiffness 1 and ElementMaterialData{} (StVK is isotropic).
/// @param xw   positions and inverse masses, updated in place
/// @param ctx  energy_floor and alpha_tilde (its x and w are not used: xw holds the state)
/// \pre no two real lanes of a batch share a vertex (one colour)
void project_stvk_membrane_batches(const Stvk& material, const MembraneBatch* batches,
                                   std::size_t count, PaddedVertex* xw,
                                   const ProjectionContext& ctx, double* lambda,
                                   BatchIsa isa = BatchIsa::Auto);

/// The batched membrane projection of a material, for the coloured order's fast path. A material
/// without one (the default) takes the per-constraint kernels; a material gets the fast path by
/// specializing this trait with value = true and a `project` with the signature below (the
/// solver never tests for a material type).
template <class M>
struct BatchedMembraneProjection {
  static constexpr bool value = false;
};

template <>
struct BatchedMembraneProjection<Stvk> {
  static constexpr bool value = true;
  static void project(const Stvk& material, const MembraneBatch* batches, std::size_t count,
                      PaddedVertex* xw, const ProjectionContext& ctx, double* lambda) {
    project_stvk_membrane_batches(material, batches, count, xw, ctx, lambda);
  }
};

/// Projects `count` membrane batches of a frame-based material (math-spec 4.2-4.4, 6.2-6.4):
/// the current edge-aligned frame with orientation ctx.orientation, the material's 2x2 PK1 and
/// its lift, four lanes at a time; otherwise as project_stvk_membrane_batches (the same contract
/// per lane as project_membrane with stiffness 1, guards included: a frame-dependent material
/// skips a triangle without a regular frame, Mooney-Rivlin projects it on the collapsed frame).
/// \pre no two real lanes of a batch share a vertex (one colour)
void project_linear_membrane_batches(const Linear& material, const MembraneBatch* batches,
                                     std::size_t count, PaddedVertex* xw,
                                     const ProjectionContext& ctx, double* lambda,
                                     BatchIsa isa = BatchIsa::Auto);
/// See project_linear_membrane_batches.
void project_corotated_membrane_batches(const Corotated& material, const MembraneBatch* batches,
                                        std::size_t count, PaddedVertex* xw,
                                        const ProjectionContext& ctx, double* lambda,
                                        BatchIsa isa = BatchIsa::Auto);
/// See project_linear_membrane_batches.
void project_mooney_rivlin_membrane_batches(const MooneyRivlin& material,
                                            const MembraneBatch* batches, std::size_t count,
                                            PaddedVertex* xw, const ProjectionContext& ctx,
                                            double* lambda, BatchIsa isa = BatchIsa::Auto);

template <>
struct BatchedMembraneProjection<Linear> {
  static constexpr bool value = true;
  static void project(const Linear& material, const MembraneBatch* batches, std::size_t count,
                      PaddedVertex* xw, const ProjectionContext& ctx, double* lambda) {
    project_linear_membrane_batches(material, batches, count, xw, ctx, lambda);
  }
};

template <>
struct BatchedMembraneProjection<Corotated> {
  static constexpr bool value = true;
  static void project(const Corotated& material, const MembraneBatch* batches, std::size_t count,
                      PaddedVertex* xw, const ProjectionContext& ctx, double* lambda) {
    project_corotated_membrane_batches(material, batches, count, xw, ctx, lambda);
  }
};

template <>
struct BatchedMembraneProjection<MooneyRivlin> {
  static constexpr bool value = true;
  static void project(const MooneyRivlin& material, const MembraneBatch* batches,
                      std::size_t count, PaddedVertex* xw, const ProjectionContext& ctx,
                      double* lambda) {
    project_mooney_rivlin_membrane_batches(material, batches, count, xw, ctx, lambda);
  }
};

/// Projects `count` anisotropic batches of fibre energy A in order, each lane as the solver's
/// per-face call with the lane's orientation and fibre: `paper` (PBD only, lambda == nullptr):
/// project_anisotropic_paper with the lane's k_A and normal (math-spec 9.3); else
/// project_membrane with stiffness 1, PBD or XPBD (multiplier of lane k of batch b at
/// lambda[4 b + k]). Defined for AnisotropicArap, AnisotropicStvk, AnisotropicSqrt and
/// ActiveFiber (aniso_batches.cpp). xw and ctx as for project_stvk_membrane_batches (ctx's
/// orientation is not used: each lane has its own).
/// \pre no two real lanes of a batch share a vertex (one colour)
template <class A>
void project_aniso_batches(const A& material, const AnisoBatch* batches, std::size_t count,
                           PaddedVertex* xw, const ProjectionContext& ctx, double* lambda,
                           bool paper, BatchIsa isa = BatchIsa::Auto);

/// True for the fibre energies that project_aniso_batches is defined for.
template <class A>
struct BatchedAnisoProjection {
  static constexpr bool value = std::is_same_v<A, AnisotropicArap> || std::is_same_v<A, AnisotropicStvk> ||
                                std::is_same_v<A, AnisotropicSqrt> || std::is_same_v<A, ActiveFiber>;
};

/// Projects `count` isometric hinge batches in order (project_isometric_hinge per lane, math-spec
/// 8.2): PBD when lambda == nullptr, else XPBD with the 3-vector multiplier of lane k of batch b
/// at lambda[12 b + 3 k .. 12 b + 3 k + 2]. xw and ctx as for project_stvk_membrane_batches.
/// \pre no two real lanes of a batch share a vertex (one colour)
void project_isometric_hinge_batches(const IsometricBatch* batches, std::size_t count,
                                     double k_bending, PaddedVertex* xw,
                                     const ProjectionContext& ctx, double* lambda,
                                     BatchIsa isa = BatchIsa::Auto);

/// Projects `count` dihedral hinge batches in order (project_dihedral_hinge per lane, math-spec
/// 8.3): PBD when lambda == nullptr, else XPBD with the multiplier of lane k of batch b at
/// lambda[4 b + k]. The AVX2 path takes the four lanes' angles from one four-lane atan2
/// (batch_atan2's, a few ulp from std::atan2) and divides by reciprocals, so it agrees with the
/// scalar kernel to rounding, not bit for bit. xw and ctx as for project_stvk_membrane_batches.
/// \pre no two real lanes of a batch share a vertex (one colour)
void project_dihedral_hinge_batches(const DihedralBatch* batches, std::size_t count,
                                    double k_bending, PaddedVertex* xw,
                                    const ProjectionContext& ctx, double* lambda,
                                    BatchIsa isa = BatchIsa::Auto);

/// The four-lane atan2 of the AVX2 dihedral kernel (src/pbd/batch_lanes.hpp) on n pairs
/// (theta[i] = atan2(y[i], x[i]) to a few ulp), for its accuracy test against std::atan2.
/// @return false, writing nothing, when this CPU or build has no AVX2 path
bool batch_atan2(const double* y, const double* x, double* theta, std::size_t n);

}  // namespace shellcontract
