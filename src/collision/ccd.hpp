// Continuous collision detection, narrow phase (math-spec 10.3-10.6 and 11): vertex-face (VF) and
// edge-edge (EE) tests over one linear step t in [0, 1], conservative in floating point.
//
// Eigen only (house-style.md section 1); interval or exact arithmetic, if any, stays in src/collision.
//
// Stencil order (the same as the benchmark files, shared/data/ccd-queries/README.md):
//   VF: x[0] = the vertex p, x[1..3] = the triangle f0, f1, f2.
//   EE: x[0], x[1] = edge a (a0, a1); x[2], x[3] = edge b (b0, b1).
// Positions move linearly: x_k(t) = x0[k] + t (x1[k] - x0[k]) (math-spec 10.1).
//
// Contract: if the primitives come within distance `tolerance` of each other at some t in [0,1]
// (touching counts), the test reports a hit. It never misses such a contact, whatever the
// rounding, provided the inputs are finite doubles; it may report a hit for a near miss whose
// distance cannot be told apart from `tolerance` within rounding (a false positive, flagged by
// CcdResult::certain == false).
#pragma once

#include <array>

#include "shellcontract/types.hpp"

namespace shellcontract {

/// The two elementary CCD tests.
enum class CcdPrimitive {
  VertexFace,  ///< x = (p, f0, f1, f2)
  EdgeEdge,    ///< x = (a0, a1, b0, b1)
};

/// Four points of one stencil, in the order of the file comment.
using CcdStencil = std::array<Vec3, 4>;

/// Default minimum separation tau: 0, i.e. exactly the benchmark's collision definition (touching
/// counts). The error bounds make a hit reported whenever floating point cannot prove a gap.
static constexpr double DEFAULT_CCD_TOLERANCE = 0.0;
/// Default deepest bisection level of the time interval: a leaf is 2^-48 of the step wide.
static constexpr int DEFAULT_CCD_MAX_DEPTH = 48;
/// Default cap on the time intervals examined by one query; when it is reached the query is
/// reported as a (not certain) hit, which keeps the cost bounded and the answer conservative.
static constexpr int DEFAULT_CCD_MAX_INTERVALS = 4096;

/// Options of one narrow-phase query.
struct CcdOptions {
  /// tau: report a hit if the distance is <= tau at some t in [0,1]. Caller's length units, >= 0.
  /// Default DEFAULT_CCD_TOLERANCE (0).
  double tolerance = DEFAULT_CCD_TOLERANCE;
  /// Deepest bisection level of [0,1] (1..60). Default DEFAULT_CCD_MAX_DEPTH.
  int max_depth = DEFAULT_CCD_MAX_DEPTH;
  /// Cap on examined time intervals per query (>= 1). Default DEFAULT_CCD_MAX_INTERVALS.
  int max_intervals = DEFAULT_CCD_MAX_INTERVALS;
  /// Tighten the lower bound toi inside the deciding interval: for a hit decided by distance
  /// (CcdHitReason::Distance) after t = 0 by a greedy descent over [ta, tm] (up to 32 more
  /// interval tests, most of the cost of such a query); for the other hits by bisecting with the
  /// coplanarity test (up to 40 levels). Off, toi is the start of the deciding interval, still a
  /// valid lower bound; hit and reason are the same either way, and so are weights, normal and
  /// side unless the tightened toi passes the estimated contact time (then they are evaluated
  /// at toi). The collision response does not use toi and turns it off.
  bool tighten_toi = true;
};

/// How a hit was decided (for statistics and for callers that want certainty).
enum class CcdHitReason {
  None,            ///< no hit
  Crossing,        ///< proven: the coplanarity cubic changes sign in an interval throughout which
                   ///< the point stays strictly inside the triangle / the edges strictly cross,
                   ///< seen along a fixed direction (exact certificate, math-spec 10.5-10.6)
  Distance,        ///< the computed distance at a sample time is <= tau (+ rounding bound)
  Undecided,       ///< the finest interval could be neither excluded nor confirmed
  Budget,          ///< CcdOptions::max_intervals reached
  NonFiniteInput,  ///< an input coordinate is NaN or infinite: reported as a hit, to be safe
};

/// Result of one query. When hit is false only `intervals` is meaningful.
struct CcdResult {
  bool hit = false;
  /// True if the hit is certain (Crossing, or a distance clearly below tau); false for the
  /// conservative answers (Undecided, Budget, NonFiniteInput, or a distance within rounding).
  bool certain = false;
  CcdHitReason reason = CcdHitReason::None;
  /// Time of impact: a lower bound in [0,1] of the first time the distance is <= tau. Every
  /// earlier time is proven free (it is the start of the first time interval that could not be
  /// excluded, refined by the coplanarity test). 1 when there is no hit.
  double toi = 1.0;
  /// Time in [toi, 1] at which the contact data below were evaluated (the estimated root of the
  /// coplanarity cubic in the deciding interval, else that interval's midpoint).
  double contact_time = 1.0;
  /// Signed weights w of the stencil points such that the contact vector is
  /// sum_k w_k x_k (math-spec 10.6/10.8): VF (1, -alpha0, -alpha1, -alpha2) = p minus its closest
  /// point on the triangle; EE (1-s, s, -(1-r), -r) = point on edge a minus point on edge b.
  Eigen::Vector4d weights = Eigen::Vector4d(1.0, -1.0, 0.0, 0.0);
  /// Unit contact normal n_c (math-spec 10.6): VF the triangle normal at contact_time; EE the unit
  /// (a1-a0) x (b1-b0) at contact_time, else the closest-point direction at t = 0.
  Vec3 normal = Vec3::UnitZ();
  /// sigma_c in {-1, +1}: sign of n_c . (sum_k w_k x_k) at t = 0, the side the primitives started
  /// on (math-spec 10.6). If that is 0 it is the opposite of the sign of the approach velocity,
  /// and +1 if both are 0.
  double side = 1.0;
  /// Number of time intervals examined (a measure of the cost of the query).
  int intervals = 0;
};

/// Vertex-face CCD over one step.
/// @param x0       positions at t = 0: (p, f0, f1, f2), any length unit
/// @param x1       positions at t = 1, same order and unit
/// @param options  tolerance tau in the same unit, and the search limits
/// @return hit or not; for a hit, the time of impact and the contact data (see CcdResult)
CcdResult vertex_face_ccd(const CcdStencil& x0, const CcdStencil& x1,
                          const CcdOptions& options = {});

/// Edge-edge CCD over one step.
/// @param x0       positions at t = 0: (a0, a1, b0, b1), any length unit
/// @param x1       positions at t = 1, same order and unit
/// @param options  tolerance tau in the same unit, and the search limits
/// @return hit or not; for a hit, the time of impact and the contact data (see CcdResult)
CcdResult edge_edge_ccd(const CcdStencil& x0, const CcdStencil& x1,
                        const CcdOptions& options = {});

/// Dispatches to vertex_face_ccd or edge_edge_ccd.
/// @param kind     which test
/// @param x0       positions at t = 0 in the stencil order of `kind`
/// @param x1       positions at t = 1
/// @param options  tolerance and limits
/// @return see CcdResult
CcdResult primitive_ccd(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1,
                        const CcdOptions& options = {});

/// Power-form coefficients (c0, c1, c2, c3) of the coplanarity cubic
/// f(t) = ((u + t du) x (v + t dv)) . (w + t dw) (math-spec 10.3). VF: u = f1-f0, v = f2-f0,
/// w = p-f0, so f > 0 when p is on the side of the normal (f1-f0) x (f2-f0). EE: u = a1-a0,
/// v = b0-a0, w = b1-a0.
/// @param kind  stencil order
/// @param x0    positions at t = 0 (length unit L)
/// @param x1    positions at t = 1
/// @return c0..c3 in L^3, plain double evaluation (no error bound)
std::array<double, 4> coplanarity_cubic(CcdPrimitive kind, const CcdStencil& x0,
                                        const CcdStencil& x1);

/// Bernstein coefficients (b0..b3) of the same cubic on [0,1], computed from the end positions
/// only: b_k = (sum over i+j+l = k of det(u_i, v_j, w_l)) / C(3,k) with u_0, u_1 the values at
/// t = 0 and t = 1 (the blossom; equal to math-spec 10.4's formulas).
/// @return b0..b3 in L^3
std::array<double, 4> coplanarity_bernstein(CcdPrimitive kind, const CcdStencil& x0,
                                            const CcdStencil& x1);

/// Tang, Manocha and Tong's (2010) geometric form of the Bernstein coefficients (math-spec 10.4):
/// with n0 = u0 x v0, n1 = u1 x v1, n_hat = (n0 + n1 - du x dv)/2:
/// b0 = w0.n0, b1 = (2 w0.n_hat + w1.n0)/3, b2 = (2 w1.n_hat + w0.n1)/3, b3 = w1.n1.
/// @return b0..b3 in L^3 (for cross-checks; the narrow phase uses coplanarity_bernstein)
std::array<double, 4> tang_bernstein(CcdPrimitive kind, const CcdStencil& x0,
                                     const CcdStencil& x1);

/// Converts power-form coefficients to Bernstein coefficients on [0,1] (math-spec 10.4):
/// b0 = c0, b1 = c0 + c1/3, b2 = c0 + 2c1/3 + c2/3, b3 = c0 + c1 + c2 + c3.
/// @param c  c0..c3
/// @return b0..b3
std::array<double, 4> bernstein_from_power(const std::array<double, 4>& c);

/// The rounding-error bound of nonpenetration_filter_culls; both are rigorous (ccd.cpp). Their
/// answers differ only for stencils whose coefficients lie between the two bounds, i.e. within
/// about 1e-14 |u| |v| |w| of the threshold: coplanar to within rounding (tau = 0), or at
/// distance tau to within rounding.
enum class FilterBound {
  /// 16 u times the magnitude sum of each coefficient's products: the smallest bound, most culls.
  Tight,
  /// 32 u max|u|_inf max|v|_inf max|w|_1 over both times: at least as large (but for the
  /// rounding of either; much larger for flat stencils), a fifth of the arithmetic. The
  /// collision step's batched filter (cull_batch) uses it; with tau > 0 the tolerance term
  /// dwarfs either bound.
  Coarse,
};

/// Deforming non-penetration filter (Tang et al. 2010, math-spec 10.4) made certain in floating
/// point: true only if, with every rounding error bounded, all Bernstein coefficients of the
/// coplanarity cubic are > tau N or all are < -tau N, where N bounds the normal's length over the
/// step. Then the four points are never coplanar (tau = 0) or never closer than tau to the
/// plane/line of the other primitive, so no contact within tau is possible.
/// @param kind       stencil order
/// @param x0         positions at t = 0
/// @param x1         positions at t = 1
/// @param tolerance  tau >= 0 in the same length unit
/// @param bound      which rounding bound (FilterBound)
/// @return true if the pair can be culled (no contact within tau in [0,1])
bool nonpenetration_filter_culls(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1,
                                 double tolerance = 0.0, FilterBound bound = FilterBound::Tight);

/// Separating-axis cull over the whole step (the narrow phase's step 2 on [0,1], ccd.cpp): true
/// only if, along one of the axes x, y, z or along the closest-point direction at t = 1/2, every
/// vertex difference (VF: p - f_i; EE: a_i - b_j) at t = 0 and at t = 1 lies beyond tau, with the
/// rounding bounded. Every relative vector of the two primitives during the step is a convex
/// combination of those differences (linear motion), so their distance stays above tau. This is
/// what settles most pairs that pass the non-penetration filter but are far apart within a
/// common plane (neighbours on a flat sheet): on bear's collision step it settles most of the
/// narrow-phase queries, at a fraction of the interval search's cost, so the two together cost
/// less than the interval search alone (lab/history.md). A pair it culls is one the interval
/// search (vertex_face_ccd,
/// edge_edge_ccd) reports as no hit.
/// @param kind       stencil order
/// @param x0         positions at t = 0
/// @param x1         positions at t = 1
/// @param tolerance  tau >= 0 in the same length unit
/// @return true if the pair can be culled (no contact within tau in [0,1]); false for non-finite
///         input
bool separating_axis_culls(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1,
                           double tolerance = 0.0);

/// The two halves of separating_axis_culls, which is true iff one of them is: the axes x, y, z
/// alone (its step 2a; cull_batch also gives it four stencils at a time), and the closest-point
/// direction at t = 1/2 alone (step 2b). Same parameters and the same false for non-finite input.
bool separating_axes_culls(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1,
                           double tolerance = 0.0);
bool separating_direction_culls(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1,
                                double tolerance = 0.0);

/// Swept-box cull (math-spec 10.2, per pair): true only if the boxes around the two primitives'
/// start and end positions (VF: the vertex against the face; EE: edge against edge) are more than
/// tau apart on some axis, with the rounding of the gap bounded. Then their distance exceeds tau at
/// every time in [0,1] (linear motion stays inside the swept box). Costs a few nanoseconds and
/// runs before the non-penetration filter, so pairs a broad phase with a reuse margin kept (boxes
/// inflated by more than tau) leave cheaply.
/// @param kind       stencil order
/// @param x0         positions at t = 0
/// @param x1         positions at t = 1
/// @param tolerance  tau >= 0 in the same length unit
/// @return true if the pair can be culled (no contact within tau in [0,1]); false for non-finite
///         input
bool swept_boxes_apart(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1,
                       double tolerance = 0.0);

}  // namespace shellcontract
