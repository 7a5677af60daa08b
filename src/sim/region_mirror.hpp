// The local contraction's dimple as a shape (docs/math/region-mirror.md): the region's cap mirrored
// through the plane of its rim. A reflection keeps every edge length and every angle, so a dimple
// that reaches its mirror image strains none of its faces and the rest of the shell has nothing to
// answer; the volume projection of region_volume.hpp only fixes the cap's volume, and the strained
// shape it reaches pulls on its rim. Eigen only.
#pragma once

#include <optional>
#include <vector>

#include "shellcontract/types.hpp"
#include "sim/region_volume.hpp"

namespace shellcontract {

/// A plane through `point` with unit `normal`.
struct MirrorPlane {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
};

/// x -> scale * rotation * x + translation (rotation proper, scale > 0).
struct Similarity {
  Mat3 rotation = Mat3::Identity();
  double scale = 1.0;
  Vec3 translation = Vec3::Zero();
  Vec3 operator()(const Vec3& x) const { return scale * (rotation * x) + translation; }
};

/// The image of p in the plane: p - 2 ((p - point) . normal) normal. An isometry.
Vec3 reflect(const Vec3& p, const MirrorPlane& plane);

/// The similarity that maps `from` onto `to` best in least squares (Umeyama 1991: the SVD of the
/// centred cross-covariance, its reflection turned into a rotation). nullopt when the sizes differ,
/// there are fewer than 3 points, or either set is collinear or a point (the rotation about the
/// line, or the scale, is then not determined).
std::optional<Similarity> fit_similarity(const std::vector<Vec3>& from,
                                         const std::vector<Vec3>& to);

/// Why a region cannot be mirrored (it then keeps the volume projection).
enum class MirrorFallback {
  None,              ///< mirrorable
  NoRim,             ///< fewer than 3 rim vertices (a closed component, or nothing)
  CollinearRim,      ///< the rim's points lie on a line: no plane, no frame
  NoArea,            ///< the region's area vector vanishes: no side to mirror to
  NoInteriorVertex,  ///< every vertex is on the rim (e.g. a single face): nothing to move
};

/// A short phrase for the fallback ("collinear rim", ...).
const char* mirror_fallback_name(MirrorFallback f);

/// The rest data of a cap's mirror: the plane through the rest rim's centroid, normal to the cap's
/// rest area vector (the rim polygon's vector area: its plane for a flat rim, outward), and the
/// interior vertices' mirror images, all relative to the rest rim's centroid.
struct RegionMirror {
  MirrorFallback fallback = MirrorFallback::NoRim;
  MirrorPlane plane;
  Vec3 rest_centre = Vec3::Zero();  ///< the rest rim's centroid
  std::vector<Vec3> rest_rim;       ///< rest rim points minus their centroid (cap.rim order)
  std::vector<int> moved;           ///< indices into cap.vertices of the interior vertices
  std::vector<Vec3> image;          ///< their mirror images, minus the rest rim's centroid
  /// [i] != 0: moved[i] shares a face with a rim vertex (the crease ring). apply_region_mirror_in
  /// leaves these to the solver when asked: the rim of a face prefix is not flat, so a crease
  /// ring pinned to its images strains the faces at the rim, which pull on the shell every step.
  /// All 0 when no interior vertex lies beyond the crease ring (a dimple of one ring still sinks).
  std::vector<char> crease;
  /// [i]: the longest step moved[i] takes toward its image in one call when MirrorStep::clamp
  /// is set: half the shortest rest edge of the cap's faces at it (+inf if all those edges are 0).
  std::vector<double> max_step;
};

/// The mirror of `cap` at the rest positions (fallback set when it has none).
RegionMirror make_region_mirror(const Positions& rest, const RegionCap& cap);

/// Moves each interior vertex of the cap a share `beta` in (0, 1] of the way to its mirror image
/// carried into the current frame: the similarity that best maps the rest rim onto the rim at x,
/// so a shell that moves, turns or shrinks carries its dimples along. Rim vertices, held ones
/// (held[v] != 0) and those with w = 0 stay. Returns false, moving nothing, when the mirror has a
/// fallback or the current rim gives no similarity (collapsed onto a line).
bool apply_region_mirror(Positions& x, const RegionCap& cap, const RegionMirror& mirror,
                         const Eigen::VectorXd& w, const std::vector<char>& held, double beta);

/// The similarity that carries the rest positions of `vertices` onto their positions at x (the
/// shell's own frame when `vertices` are those away from every region): it does not depend on
/// the regions' rims, so a rim pulled in by its dimple does not move the dimple's target.
/// nullopt when fit_similarity has none (fewer than 3 vertices, collinear).
std::optional<Similarity> shell_frame(const Positions& rest, const Positions& x,
                                      const std::vector<int>& vertices);

/// How apply_region_mirror_in moves a dimple's vertices.
struct MirrorStep {
  double beta = 1.0;         ///< share of the way to the image, in (0, 1]
  /// Leave the crease ring (RegionMirror::crease) to the solver, which bends the fold where the
  /// shell gives the least.
  bool free_crease = false;
  /// The image is a mould, not a place: a vertex already on the inner side of its image (along
  /// the frame's plane normal; a load pushed it deeper) stays where it is.
  bool one_sided = false;
  /// Each vertex moves at most RegionMirror::max_step toward its image per call, as a constraint
  /// projection's step is clamped. Unclamped, a vertex whose image lies behind another part of
  /// the shell (a limb flattened by the pressure) jumps the whole way there, the collision
  /// response throws it back, it is left alone for one step as held by contact, and jumps again:
  /// a flicker every other frame, and a crowd of contacts per step (lab/regions/mirror_step.md).
  /// Clamped, it comes to rest against the obstacle; an image that can be reached is reached a
  /// few steps later, since the dimple grows with a ramp of many steps.
  bool clamp = false;
};

/// Moves each interior vertex of the cap a share step.beta of the way to its mirror image carried
/// by `frame` (from the rest positions' coordinates to the current ones); rim vertices, held ones
/// (held[v] != 0) and those with w = 0 stay, and `step` may leave more alone. Returns false,
/// moving nothing, when the mirror has a fallback.
bool apply_region_mirror_in(Positions& x, const RegionCap& cap, const RegionMirror& mirror,
                            const Similarity& frame, const Eigen::VectorXd& w,
                            const std::vector<char>& held, const MirrorStep& step);

/// apply_region_mirror (the frame fitted to the rim), moving as `step` says (beta = step.beta).
bool apply_region_mirror(Positions& x, const RegionCap& cap, const RegionMirror& mirror,
                         const Eigen::VectorXd& w, const std::vector<char>& held,
                         const MirrorStep& step);

}  // namespace shellcontract
