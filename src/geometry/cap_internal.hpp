// Private to the region finders (cap_finder.cpp, cap_arrays.cpp, cap_shape.cpp, and the tip
// and part finders tip_finder.cpp and part_finder.cpp, which reuse their helpers): the mesh as
// flat arrays, a grown cap and its final shape.
#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "core/constants.hpp"
#include "geometry/curvature.hpp"
#include "geometry/sphere_moments.hpp"
#include "shellcontract/mesh.hpp"
#include "shellcontract/regions.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {
struct CurvatureField;
}

namespace shellcontract::detail {

/// Runs a public function's `search` under a scope that asks options.cancelled, when it is set,
/// and turns its stop into RegionSearchCancelled("`who`: cancelled"): PreparationCancelled must
/// not leave the library. Without a hook `search` runs as is (under a run's scope, if any).
std::vector<int> with_cancel_hook(const RegionOptions& options, const char* who,
                                  const std::function<std::vector<int>()>& search);

/// Mesh arrays the finder works on (vertex and face indices = idx()).
struct MeshArrays {
  std::size_t nv = 0, nf = 0;
  std::vector<std::array<int, 3>> tri;
  std::vector<double> face_area, vertex_area;            ///< vertex: a third of the incident faces
  /// Vertex v's neighbours nbr_to[k] at edge length nbr_len[k], k in [nbr_start[v],
  /// nbr_start[v + 1]) (flat arrays: the disc growth visits millions of them).
  std::vector<int> nbr_start, nbr_to;
  std::vector<double> nbr_len;
  std::vector<std::array<int, 3>> face_nbr;              ///< across each edge, -1 on a border
  std::vector<std::vector<int>> vertex_faces;
  double total_area = 0.0, size = 0.0;  ///< size = sqrt(total_area)
};

MeshArrays mesh_arrays(const Mesh& mesh, const Positions& x);

/// What every finder starts from: the curvature (compute_curvature also checks the mesh: garbage,
/// sizes, degree) and the mesh arrays.
struct FinderStart {
  CurvatureField curvature;
  MeshArrays arrays;
  /// No vertex or no area: there is nothing to find.
  bool empty() const { return arrays.nv == 0 || !(arrays.total_area > 0.0); }
};

FinderStart start_finder(const Mesh& mesh, const Positions& x);

/// A finder's answer on an empty start: no face in a region, a report holding the total area,
/// and the curvature handed to the caller where it asks for it.
std::vector<int> no_regions(FinderStart& start, RegionReport* report, CurvatureField* curvature);

/// The widest a region may be: its faces lie within this angle (radians) of its axis, seen from
/// its sphere's centre: a hemisphere. A cap wider than a hemisphere is most of a limb or of a
/// body (a paw's cap of 140 degrees reaches down the arm), and a dimple mirrored through the rim
/// of such a cap turns the limb inside out (docs/math/cap-finder.md).
constexpr double MAX_CAP_ANGLE = 0.5 * PI;

/// A grown cap, or a region: its seed, the disc's radius, its fitted sphere and its faces.
struct Cap {
  int seed = -1;
  double rho = 0.0;  ///< geodesic (edge-graph) radius of the accepted disc
  detail::SphereFit sphere;
  /// Grown: the disc's angle from its area, acos(1 - area / (2 pi r^2)); shaped (shape_cap):
  /// the widest face centroid from the axis. Radians.
  double angle = 0.0;
  bool unbounded = false;  ///< the disc still fitted when it reached max_area_fraction
  std::vector<int> faces;
};

/// The area-weighted mean direction from c to the faces' centroids, normalised; zero when
/// there is none (faces all around c).
Vec3 cap_axis(const MeshArrays& m, const Positions& x, const std::vector<int>& faces, const Vec3& c);

/// The final shape of region `id` (the part's faces in cap.faces; owner_face = region per face,
/// -1 for none): with the sphere fitted to the part and its axis (cap_axis about that centre),
/// the faces within MAX_CAP_ANGLE of the axis, flooded over the faces near the sphere (corners
/// within twice the fit's residual of the radius, 0.02 to 0.1) within that angle that no other
/// region owns; the outline smoothed, without adding a face with a corner on a concave crease
/// (crease[v] != 0: the groove between two parts side by side); the largest edge-connected
/// piece; its holes filled where they lie within the angle and hold no face of another region.
/// Updates cap.faces, cap.sphere (residual: RMS distance of the region's vertices to the sphere /
/// radius), cap.angle and owner_face. False when nothing is left or the part has no axis (faces all
/// around its centre).
bool shape_cap(const MeshArrays& m, const Positions& x, Cap& cap, std::vector<int>& owner_face,
               int id, const std::vector<char>& crease);

/// The finders run on x * 2^-k, k = finder_exponent(x) (curvature.hpp), where nothing over- or
/// underflows; a power of two changes no bit of a dimensionless quantity, so the regions are
/// those of the mesh at a usual scale. The points of --region-at likewise.
std::vector<Vec3> scaled_by_power_of_two(const std::vector<Vec3>& points, int k);
/// The report's and the curvature field's lengths, areas and curvatures of positions scaled by
/// 2^-k, back in the units of the unscaled positions. Either may be null.
void unscale_finder_results(int k, RegionReport* report, CurvatureField* curvature);
/// The --region-at point p, or the point at REGION_POINT_FAR bounding-box diagonals from the
/// box's centre in p's direction if p is farther (finder_scale.cpp); points: each of them
/// (non-finite ones as they are), with x's box.
Vec3 pulled_in(const Vec3& p, const Vec3& centre, double diagonal);
std::vector<Vec3> pulled_in(const std::vector<Vec3>& points, const Positions& x);

/// select_spherical_regions, handing out the curvature field it computed (when curvature is not
/// null): mark_spherical_regions stores it for the PLY instead of computing it a second time.
std::vector<int> select_spherical_regions(const Mesh& mesh, const Positions& x, const RegionOptions& options,
                                          RegionReport* report, CurvatureField* curvature);

/// Diffusion lengths of the smoothed mean curvature, in units of the mesh's size sqrt(total
/// area). The first marks concave spots (creases between a part and its body) without the
/// noise of a scan; the others give the seeds: a fingertip or an ear is a maximum at the
/// smaller ones, a head at the larger.
inline constexpr std::array<double, 4> SEED_SCALES = {0.01, 0.02, 0.05, 0.1};

/// Marks the corners of the cap's faces: a later cap may not grow over them.
void block(const MeshArrays& m, const Cap& cap, std::vector<char>& blocked);

/// The mean curvature c.mean smoothed by one implicit heat step per scale: (M + t L) u = M H, L
/// the cotangent Laplacian, M the mixed areas, t = (scale * m.size)^2 (cap_finder.cpp). One
/// field per scale, in the order given.
std::vector<Eigen::VectorXd> smoothed_curvature(const MeshArrays& m, const Positions& x, const CurvatureField& c,
                                                const std::vector<double>& scales);

/// Area-weighted median of |values|; 0 when the total weight is 0.
double weighted_median_abs(const Eigen::VectorXd& values, const std::vector<double>& weights);

/// The reference curvature of a mesh: the area-weighted median |u| of the curvature smoothed at
/// the largest scale, at least 1 / the bounding box's diagonal (a mostly flat mesh, a cube, must
/// not make every rounded spot "curved").
double reference_curvature(const MeshArrays& m, const Positions& x, const Eigen::VectorXd& u_largest);

/// Fills a region's summary from its cap (sphere, angle, seed) and its faces.
RegionSummary summarise(const Mesh& mesh, const Positions& x, const MeshArrays& m, const Cap& cap, double h_ref);

/// Ids by decreasing area (ties: smallest face; none when keep_order), the per-face id array,
/// and the report's list of summaries in id order.
std::vector<int> number_regions(std::vector<std::pair<Cap, RegionSummary>>& kept, std::size_t nf, RegionReport& r,
                                bool keep_order);

/// The area-weighted least-squares sphere of the corners of `faces` (origin: a point near them,
/// for conditioning); nothing when it is degenerate (SphereMoments::fit).
std::optional<SphereFit> fit_faces(const MeshArrays& m, const Positions& x, const std::vector<int>& faces, int origin);

/// Edge-connected components of the faces with flag[f] != 0, each with its area; components are
/// numbered by their smallest face, so the numbering does not depend on anything but the faces.
struct Components {
  std::vector<int> of;  ///< per face, -1 outside the flagged set
  std::vector<double> area;
  std::vector<int> first;  ///< smallest face of each component
};

Components components(const MeshArrays& m, const std::vector<char>& flag);

/// Index of the component of largest area (ties: the one with the smallest face; -1 if none).
int largest(const Components& c);

/// The faces of the largest edge-connected piece of `flag` (largest()), ascending; empty when
/// flag is.
std::vector<int> largest_piece(const MeshArrays& m, const std::vector<char>& flag);

Vec3 face_centroid(const MeshArrays& m, const Positions& x, int f);

/// A region of the tip and part finders as a report describes it: its faces and seed, the sphere
/// fitted to its faces, and its widest face centroid from its axis (seen from the centre).
Cap region_cap(const MeshArrays& m, const Positions& x, int seed, std::vector<int> faces);

/// The report's counter of the first filter a region fails (too few faces or too small a share
/// of the area, too large a share, not compact), or nullptr when it passes them all.
std::size_t* failed_filter(const RegionSummary& s, const RegionOptions& o, RegionReport& r);

}  // namespace shellcontract::detail
