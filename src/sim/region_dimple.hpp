// The local contraction's shape (docs/math/local-contraction.md, section 4): a region sinks as a
// dimple, the mirror image of a smaller cap around its apex, as a thin spherical shell does under
// a local load. A cap that is flattened must lose area and so pulls its rim and the shell around
// it in; a mirrored cap keeps its area (for a spherical cap the mirror is an isometry), so the
// shell outside the dimple has nothing to answer. Eigen only.
#pragma once

#include <vector>

#include "shellcontract/types.hpp"
#include "sim/region_mirror.hpp"
#include "sim/region_volume.hpp"

namespace shellcontract {

/// A region's faces ordered from its apex outward, with the rest cap volume of every prefix of
/// that order, and the prefix now mirrored (the dimple).
struct RegionDimple {
  RegionCap whole;                 ///< the whole region's cap, rest_volume set
  /// The cut's direction (make_region_dimple): the region's normal unless the region is cut.
  Vec3 axis = Vec3::UnitZ();
  std::vector<int> order;          ///< the region's face ids, from the apex (or the cut's top) on
  /// The faces of `order` above the cut (make_region_dimple): a prefix whose rim is near a plane
  /// section, so that its mirror image meets the shell along its rim. dimple_size_for grows the
  /// dimple no further.
  int limit = 0;
  std::vector<double> prefix_rest_volume;  ///< [k]: rest cap volume of the first k + 1 faces
  int size = 0;                    ///< faces in the current dimple (0: none yet)
  RegionCap dimple;                ///< cap of the first `size` faces of order, rest_volume set
  /// DimpleShape::Mirror: the current dimple's mirror (Simulator::resize_dimple makes it)
  RegionMirror mirror;
};

/// How far below the region's highest rim point the cut lies, in mean edge lengths of the
/// region. A rim that lies within that band of a plane is ragged, not bent: the crease ring,
/// left to the solver (region_mirror.hpp), takes it up, and the region needs no cut. Bent rims
/// (a head cut out of a body) lie several times farther off; the measured rims and the choice
/// of 3 are in lab/regions/locality.md, "The cut".
inline constexpr double CUT_TOLERANCE = 3.0;

/// The dimple order of a region at the rest positions (docs/math/region-mirror.md, section 4).
/// The apex is the region vertex farthest from the rim's centroid along the region's
/// area-weighted normal, and the faces are sorted by the distance of their centroid from it
/// (ties by face id, so the order is deterministic). Then the cut: among the normal and the
/// directions tilted from it by 10 to 60 degrees (12 azimuths each, from the direction in which
/// the rim rises, so that the cut turns with the mesh), the axis whose cut (the
/// plane normal to it through the highest rim vertex, lowered by CUT_TOLERANCE edge lengths)
/// leaves the largest cap volume above it. If a face of the region reaches below that cut, the
/// faces are instead sorted by the height of their lowest corner along the axis, highest first,
/// and `limit` counts those above the cut; otherwise `limit` is every face and `axis` the
/// normal. Face ids outside [0, #F) are skipped.
RegionDimple make_region_dimple(const Positions& rest, const Faces& faces,
                                const std::vector<int>& region_faces);

/// Cap volume (cap_volume) of every prefix of `order` at x, in one pass: with c the mean of the
/// prefix's rim vertices, V = (sum over its faces of det(x_a, x_b, x_d) - c . sum over its
/// boundary edges (i -> j) of x_i x x_j) / 6, both sums and the rim kept up to date face by face.
std::vector<double> prefix_cap_volumes(const Positions& x, const Faces& faces,
                                       const std::vector<int>& order);

/// The smallest dimple whose rest cap volume reaches `volume`: the least k >= 1 with
/// prefix_rest_volume[k - 1] >= volume, or all the faces if none does; at most d.limit faces.
int dimple_size_for(const RegionDimple& d, double volume);

/// The rest cap volume V_k of the dimple a region mirrors at ramp progress s in [0, 1] with the
/// shell, its caps cut off, at volume ratio rho: min(shrink s / rho, 1) rest_volume (the whole
/// cap at most; rho <= 0 gives the whole cap). Its mirror image at the shell's scale, -rho V_k,
/// takes 2 shrink s of the rest cap volume off the region beyond the shell's own share: on a shell
/// at rest, shrink 0.5 leaves the cap with no volume and 1 turns the whole cap inside out.
double dimple_rest_volume(double rest_volume, double shrink, double s, double rho);

/// Makes the first k faces of d.order the dimple (rebuilding its cap only when k changed).
void set_dimple_size(RegionDimple& d, const Faces& faces, int k);

}  // namespace shellcontract
