// Automatic selection of the "local spherical structures" of Sun et al. 2020 (section 3.3: a head,
// an ear, a fingertip; the paper picks them by hand): compact caps on a sphere, the parts a person
// would circle. Algorithm (docs/design/regions.md; code in cap_finder.cpp):
//   1. seeds: vertices where the mean curvature, smoothed by heat diffusion at two lengths
//      relative to the mesh's size, has a strict local maximum over its one-ring and is > 0;
//   2. every seed grows a geodesic disc (Dijkstra on the edge graph) in steps of a fixed
//      fraction of the mesh's size; at each step a least-squares sphere is fitted to the disc
//      (area-weighted); the disc keeps growing while the fit's RMS distance stays within
//      fit_tolerance of the radius, the centre stays inside (convex) and at most
//      max_concave_fraction of the disc is concave;
//   3. candidates are ranked by their angular extent (arc radius / sphere radius: a fingertip or
//      ear is close to a hemisphere, a patch of a flank is nearly flat); in that order each is
//      grown again without entering the parts already accepted and kept when it is curved
//      enough (1/radius >= min_curvature_contrast x the median |H|), spans at least
//      min_cap_angle_deg, has an area share within [min, max]_area_fraction, at least
//      min_faces faces and compactness perimeter^2 / (4 pi area) <= max_compactness. A
//      candidate whose seed lies inside a kept cap, near a kept cap's sphere (within 2.2 radii
//      of its centre) or whose free cap lies mostly on kept caps is not a part of its own: it
//      joins that part;
//   4. each part is its cap with the free caps of the candidates that joined it;
//   5. each part becomes its region: the faces within a hemisphere of the part's fitted sphere
//      (about the mean direction of its faces from the centre) that lie on that sphere or in
//      the part, in one piece, holes filled unless another region is in them, the outline
//      smoothed; filtered again (size, compactness, fit residual <= fit_tolerance), and a
//      region whose centre lies within 1.2 radii of a larger region's centre is dropped as a
//      piece of it. So no region spans more than a hemisphere (docs/math/cap-finder.md).
// Every length is relative to the mesh's size (sqrt of its area), so the result does not
// change under scaling, rotation, vertex order and (within the discretisation) resolution.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "shellcontract/mesh.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// How select_spherical_regions finds the regions.
enum class RegionMethod {
  /// Spherical caps grown from curvature seeds (the file comment's steps; the default).
  Caps,
  /// Opt-in: discs around the tips of protrusions (the ends of arms, ears, fingertips), each
  /// grown until it wraps round its end or meets a concave crease, the discs shared out by
  /// nearest centre (docs/math/tip-finder.md). Uses max_concave_fraction, max_compactness,
  /// min_faces and the area fractions; the sphere-fit thresholds (fit_tolerance,
  /// min_cap_angle_deg, min_curvature_contrast) do not apply.
  Tips,
  /// Opt-in: the tip finder's regions with the cap finder's heads and bumps: a cap region that
  /// tip regions cover at most half of is kept and grown to the ball of its fitted sphere
  /// (docs/math/part-finder.md). Reads the options of both finders.
  Parts,
};

/// Thresholds of select_spherical_regions. All are dimensionless (scale-free).
struct RegionOptions {
  /// The finder (Caps by default; the thresholds below say which method reads them).
  RegionMethod method = RegionMethod::Caps;
  /// Growth: the disc grows while the RMS distance of its points to the fitted sphere is at most
  /// this fraction of the sphere's radius. Loose on purpose: the parts a person circles are
  /// rounded, not exact spheres (an ear is a flattened lobe, a paw's end a rounded disc), and a
  /// part ends where its body begins, at a concave crease (max_concave_fraction); the fit stops
  /// a disc that runs along a shaft or a flank.
  double fit_tolerance = 0.3;
  /// Growth: at most this share of the disc's area may be concave (smoothed H < 0); the crease
  /// between a part and its body stops the growth.
  double max_concave_fraction = 0.05;
  /// Kept only when the cap spans at least this angle (geodesic radius / sphere radius, in
  /// degrees; a hemisphere spans 90): a flank is nearly flat, an ear or a paw's end is not.
  double min_cap_angle_deg = 50.0;
  /// Kept only when the cap's curvature 1/radius is at least this times the area-weighted
  /// median |H| of the surface (smoothed at the largest length): a belly, or the base sphere
  /// between bumps, is no more curved than the typical surface; a head or a ball foot is. (A
  /// plain sphere has no region anyway: its caps never end, see max_area_fraction.)
  double min_curvature_contrast = 1.1;
  /// Kept only when perimeter^2 / (4 pi area) is at most this, any value > 0 (1 = a flat disc,
  /// 0.5 = a hemisphere: a cap on a sphere is below 1; slivers, rims and L or X shapes are far
  /// above 2).
  double max_compactness = 2.0;
  /// Kept only with at least this many faces (fewer cannot be judged round).
  int min_faces = 10;
  /// Kept only when at least this fraction of the total area (noise, single spikes).
  double min_area_fraction = 0.002;
  /// Kept only when at most this fraction of the total area (a region that large is not a
  /// local part; sinking it deflates the shell). Also bounds the growth: a disc that still fits
  /// at this size has not met the end of a part and is dropped (select_regions_at keeps the
  /// largest cap within it instead).
  double max_area_fraction = 0.25;
  /// The caller's cancel request, not a threshold: asked on the calling thread between the
  /// search's stages and within its long loops (a large mesh's search hears it within a small
  /// share of its time); true stops the search with RegionSearchCancelled.
  /// Empty (the default): never asked. Python's regions() asks its signal handlers here
  /// (Ctrl-C); a run does not read it (its observer's cancelled() stops the run's region
  /// search, shellcontract/observer.hpp).
  std::function<bool()> cancelled;
};

/// The search stopped because RegionOptions::cancelled said so (Ctrl-C in Python's regions());
/// nothing is returned, and mark_spherical_regions leaves the mesh's maps as they were. A run's
/// own region search does not throw it: the run returns RunStatus::Cancelled
/// (shellcontract/run.hpp).
class RegionSearchCancelled : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One selected region, as reported by select_spherical_regions.
struct RegionSummary {
  std::size_t faces = 0;         ///< number of faces
  double area = 0.0;             ///< length^2, at the given positions
  double area_fraction = 0.0;    ///< area / total area
  Vec3 centre = Vec3::Zero();    ///< centre of the fitted sphere (length)
  double radius = 0.0;           ///< radius of the fitted sphere (length)
  double residual = 0.0;         ///< RMS distance of the region's vertices to the sphere / radius
  double cap_angle_deg = 0.0;    ///< widest angle of a face centroid from the region's axis, seen
                                 ///< from the sphere's centre, degrees (at most 90 for the cap
                                 ///< finder; a tip region is not clipped to a hemisphere)
  double compactness = 0.0;      ///< perimeter^2 / (4 pi area) of the region's faces
  /// false when no sphere was fitted: a select_regions_at point where no convex sphere fits gets
  /// its seed's one-ring as is. centre, radius, residual, cap_angle_deg, mean_curvature and
  /// contrast are then not measured (left 0).
  bool fitted = true;
  int seed_vertex = -1;          ///< vertex the region grew from
  double mean_curvature = 0.0;   ///< 1 / radius, 1/length
  double contrast = 0.0;         ///< mean_curvature / reference_mean_curvature
};

/// Time one stage of the cap finder took (RegionReport::stage_times).
struct RegionStageTime {
  std::string stage;  ///< curvature, smoothing, free growth, ranked growth, parts, shape
  double wall_s = 0;  ///< wall-clock seconds
  double cpu_s = 0;   ///< processor seconds of the whole process (all its threads)
};

/// A select_regions_at point farther from the surface than this fraction of the mesh's
/// bounding-box diagonal is a warning (RegionReport::warnings): a point picked on the surface
/// (Blender's 3D cursor, a vertex) lies within rounding of it and one read off a render within
/// about a percent, while a fitted sphere's centre (the `regions` table's centre column) or a
/// point in Blender's Z-up world for a Y-up file usually lies farther (docs/design/regions.md,
/// "Points far from the surface", has the paper meshes' distances).
constexpr double REGION_POINT_NEAR = 0.015;

/// A select_regions_at point and where its region grows from.
struct RegionPoint {
  Vec3 point = Vec3::Zero();          ///< as given
  Vec3 surface_point = Vec3::Zero();  ///< the surface point nearest to it
  double distance = 0.0;              ///< from the point to surface_point (length)
};

/// What select_spherical_regions measured and kept (for the CLI summary and for tuning).
struct RegionReport {
  double total_area = 0.0;                ///< length^2
  double reference_mean_curvature = 0.0;  ///< area-weighted median |smoothed H|, 1/length
  std::size_t seed_vertices = 0;          ///< seeds (step 1)
  std::size_t candidates = 0;             ///< seeds whose disc fitted a convex sphere (step 2)
  std::size_t dropped_small = 0;          ///< dropped by min_area_fraction or min_faces
  std::size_t dropped_large = 0;          ///< dropped by max_area_fraction
  std::size_t dropped_flat = 0;           ///< dropped by min_cap_angle_deg or the contrast
  std::size_t dropped_shape = 0;          ///< dropped by max_compactness
  std::vector<RegionSummary> regions;     ///< one per region id, in id order
  /// The cap finder's stages in order (`regions --stage-times`); the parts method gives its cap
  /// finder's, the tip finder and select_regions_at none.
  std::vector<RegionStageTime> stage_times;
  /// select_regions_at: one per point, in order (point i's region is id i); the finders none.
  std::vector<RegionPoint> points;
  /// select_regions_at: one per point farther from the surface than REGION_POINT_NEAR diagonals,
  /// naming it, its distance, the bound and the surface point taken; options named as `field`
  /// (spell_options spells them for a front end).
  std::vector<std::string> warnings;
};

/// Finds the local spherical regions of a closed triangle mesh (steps in the file comment).
///
/// @param mesh    triangle mesh, outward oriented (H > 0 on convex parts), no garbage.
/// @param x       vertex positions, #V by 3, row i = vertex i, any length unit (rest or deformed).
/// @param options thresholds (all scale-free).
/// @param report  optional; filled with the reference curvature and one summary per region.
/// @pre  x.rows() == number_of_vertices; options in range (check_region_options).
/// @return one entry per face (index = face index = input face order): the region id, or -1.
///         Ids are 0..n-1 ordered by decreasing area, ties by smallest face index.
/// @throws UsageError on a precondition failure, or a position that is not finite;
///         RegionSearchCancelled when options.cancelled said stop.
std::vector<int> select_spherical_regions(const Mesh& mesh, const Positions& x, const RegionOptions& options,
                                          RegionReport* report = nullptr);

/// The regions around given points (an artist pointing at an ear): for each point, the surface
/// point nearest to it, then the cap grown from the nearest vertex of that face as in step 2,
/// without the ranking filters (angle, contrast, compactness) but keeping the growth's
/// tolerances: the largest such cap whose region is within max_area_fraction of the total
/// area; a later point does not enter the regions of the earlier ones. A point whose cap
/// cannot be fitted (a flat or concave spot, or a bound below the smallest disc the growth
/// judges) gets the seed's one-ring, even when that is larger than the bound, so every point
/// gives a region. Ids follow the order of the points. The report's rows describe the faces
/// returned: the sphere fitted to their vertices, the residual and the angle about it; its
/// points the surface point each region grew from, and its warnings the points farther from the
/// surface than REGION_POINT_NEAR bounding-box diagonals.
/// @throws UsageError as select_spherical_regions, or when a point is not finite;
///         RegionSearchCancelled when options.cancelled said stop.
std::vector<int> select_regions_at(const Mesh& mesh, const Positions& x, const std::vector<Vec3>& points,
                                   const RegionOptions& options, RegionReport* report = nullptr);

/// The options of `shellcontract regions` and Python's regions() as the library's messages name
/// them, in backquotes (`max_area_fraction`; RegionOptions' fields but min_cap_angle and
/// contrast): spell_options spells them for a front end ("--max-area-fraction" for the CLI).
inline constexpr std::array<const char*, 9> REGION_OPTION_FIELDS = {
    "method",          "fit_tolerance", "max_concave_fraction", "min_cap_angle",    "contrast",
    "max_compactness", "min_faces",     "min_area_fraction",    "max_area_fraction"};

/// The range of a real threshold, named as in REGION_OPTION_FIELDS, in words: "a finite number
/// >= 0" (fit_tolerance, contrast), "a finite number > 0" (max_compactness), "a number in
/// [0, 1]" (max_concave_fraction, the area fractions), "a number of degrees in [0, 180]"
/// (min_cap_angle); empty for another name.
std::string region_option_range(const std::string& field);

/// Whether `value` is in region_option_range(field) (false for NaN, an infinity or another name).
bool in_region_option_range(const std::string& field, double value);

/// The finder a method's name selects, as `regions --method` and Python's regions(method=) take
/// it ("caps", "tips", "parts"); nullopt for any other text.
std::optional<RegionMethod> region_method_named(std::string_view name);

/// The methods' names for a refusal of another: "caps, tips or parts", each between `quote`s
/// ("'caps', 'tips' or 'parts'" for "'").
std::string region_method_names(const std::string& quote = "");

/// Throws UsageError naming the first option out of range with its value and range ("`contrast`
/// nan: must be a finite number >= 0"; min_faces >= 1), or the area fractions with both values
/// when max_area_fraction is below min_area_fraction; options named as in REGION_OPTION_FIELDS.
void check_region_options(const RegionOptions& options);

/// The same selection on the mesh's own property maps (architecture.md, data flow: curvature ->
/// spherical regions -> f:region): stores the curvature at x in "v:mean_curvature" and
/// "v:gaussian_curvature" (store_curvature), selects the regions from those maps, and stores the
/// ids in "f:region" (store_regions). Maps already attached are overwritten.
/// @param mesh, x, options, report as select_spherical_regions (same @pre)
/// @return the number of regions (ids 0..n-1 in f:region)
/// @throws UsageError as select_spherical_regions; RegionSearchCancelled (the mesh's maps
///         unchanged) when options.cancelled said stop
std::size_t mark_spherical_regions(Mesh& mesh, const Positions& x, const RegionOptions& options,
                                   RegionReport* report = nullptr);

/// Writes the region ids into the face map "f:region" (properties.hpp), creating it if missing
/// and overwriting it otherwise.
/// @param region_of_face one entry per face, id or -1.
/// @throws UsageError if the size differs from number_of_faces, an id is below -1, or the mesh has
///         removed elements (Surface_mesh garbage: collect it first).
void store_regions(Mesh& mesh, const std::vector<int>& region_of_face);

/// The ids of the face map "f:region": one entry per face, -1 for no region; all -1 when the
/// map is not attached.
std::vector<int> stored_regions(const Mesh& mesh);

/// Groups per-face ids into face lists: result[r] = faces with id r, ascending.
/// @param region_of_face one entry per face, id >= 0 or -1 (ignored).
/// @return max id + 1 lists (empty for an id that no face uses).
std::vector<std::vector<int>> regions_from_face_ids(const std::vector<int>& region_of_face);

/// Inverse of regions_from_face_ids.
/// @param regions   face lists; faces must be in [0, num_faces) and in at most one list.
/// @param num_faces number of faces of the mesh.
/// @return one id per face (-1 where no list has the face).
/// @throws UsageError if a face is out of range or listed twice.
std::vector<int> face_ids_from_regions(const std::vector<std::vector<int>>& regions, std::size_t num_faces);

/// Reads a region face-list file: one line per region, its 0-based face indices (input face
/// order) separated by spaces or tabs. Blank lines and lines starting with '#' are skipped (they
/// are not regions).
/// @param path      file to read.
/// @param num_faces number of faces of the mesh the file refers to (for the range check).
/// @return the regions in file order, each with the faces in file order.
/// @throws InputError "<path>:<line>: <problem>" for a token that is not a non-negative integer,
///         an index >= num_faces, or a face listed twice (in one region or in two); and
///         "<path>: cannot open" when the file cannot be read.
std::vector<std::vector<int>> read_region_file(const std::string& path, std::size_t num_faces);

/// The regions of a face-list file with a strength each.
struct RegionFile {
  std::vector<std::vector<int>> regions;  ///< as read_region_file returns them
  std::vector<double> strength;           ///< one per region, in [0, 1]; 1 where the line gives none
};

/// read_region_file, where a line may start with its region's strength: a number in [0, 1]
/// followed by ':' ("0.5: 12 13 14"), the share of --region-shrink that region sinks with; a line
/// without one is at full strength. So a plain face list reads as before.
/// @throws InputError "<path>:<line>: <problem>" as read_region_file, and for a strength that is
///         not a number in [0, 1] or a strength with no face after it.
RegionFile read_region_file_with_strengths(const std::string& path, std::size_t num_faces);

/// Writes the regions of `region_of_face` in the format read_region_file reads: line r = the
/// faces with id r, ascending, separated by single spaces. Written atomically (temporary file
/// + rename).
/// @param region_of_face one entry per face, id or -1; the ids used must be 0..n-1 without a
///        gap (an empty line would be skipped on reading and shift the later ids).
/// @throws UsageError if an id is below -1 or an id in 0..max has no face, or the file cannot be
///         written.
void write_region_file(const std::string& path, const std::vector<int>& region_of_face);

/// Display colour of a region: id >= 0 gets a saturated hue stepped by the golden angle (so
/// neighbouring ids differ strongly and no two of the first few dozen look alike); -1 is grey.
/// @return {red, green, blue}, 0..255.
std::array<unsigned char, 3> region_colour(int id);

/// Writes the regions stored on the mesh as a PLY (the file write_ply_atomic gives: ASCII, 17
/// significant digits, vertex and face order kept, atomic) at positions x: per face `red green blue alpha`
/// (region_colour) and `int region` from "f:region"; per vertex `double mean_curvature` and
/// `double gaussian_curvature` when those maps are attached (mark_spherical_regions stores them).
/// A mesh welded along its seams (mesh_io.hpp, "Seams") is written with its input's vertices and
/// faces, as mesh_for_output gives them: each copy at its welded vertex's position and with its
/// curvature; faces (and so the region ids) in the mesh's face order.
/// @param x #V by 3 positions, row i = vertex i; or (a welded mesh) one row per input vertex.
/// @throws UsageError when x does not match the mesh or the file cannot be written;
///         std::invalid_argument (nothing written) for a position that is not finite.
void write_region_ply(const std::string& path, const Mesh& mesh, const Positions& x);

}  // namespace shellcontract
