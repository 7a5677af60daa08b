// Automatic selection of the "local spherical structures" of Sun et al. 2020 (section 3.3: a head,
// a bump; the paper picks them by hand) from discrete curvature, and the region face-list file.
//
// The selection (select_spherical_regions) in four steps:
//   1. curvature (geometry/curvature.hpp) at the given positions, optionally averaged over
//      vertex rings: H and K become area-weighted means over the ring (for K that is the total
//      angle deficit of the ring divided by its mixed area, i.e. the integrated Gaussian
//      curvature; averaging suppresses the per-vertex noise of scanned meshes);
//   2. a vertex is a *seed* when it is convex (H > 0, K > 0), close to umbilic
//      (k_min / k_max >= min_principal_ratio, both from the averaged H and K) and clearly more
//      curved than the rest of the surface (H >= min_curvature_contrast * H_ref, H_ref = the
//      area-weighted median of |H| over the mesh, floored at REFERENCE_FLOOR / bbox diagonal);
//   3. a face is selected when at least min_seed_vertices of its corners are seeds (a vertex's
//      curvature stands for its whole one-ring, so 1 = the seeds' one-ring);
//   4. PMP::connected_components on the selected faces (edge-connected); patches with less than
//      min_area_fraction or more than max_area_fraction of the total area are dropped.
// Every threshold is a ratio, so the result does not change when the mesh is scaled.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "shellcontract/core/types.hpp"
#include "shellcontract/geometry/curvature.hpp"
#include "shellcontract/mesh/surface_mesh.hpp"

namespace shellcontract {

/// Thresholds of select_spherical_regions. All are dimensionless (scale-free).
struct RegionOptions {
  /// Rings of the vertex neighbourhood over which H and K are averaged before the tests
  /// (0 = the vertex's own values). 1 removes most of the noise of scanned meshes while keeping
  /// bumps a few rings wide.
  int smoothing_rings = 1;
  /// Close to umbilic: k_min / k_max of the averaged curvature must be at least this. 1 is a
  /// perfect sphere; a cylinder has 0. 0.5 accepts ellipsoid-like caps with axis ratios up to
  /// about 2:1 and rejects ridges, finger shafts and saddles. Equivalent to
  /// H^2 - K <= ((1 - r) / (1 + r))^2 H^2 = H^2 / 9 at r = 0.5.
  double min_principal_ratio = 0.5;
  /// Clearly more curved than the surroundings: H >= this times H_ref (the area-weighted median
  /// of |H|, i.e. the curvature of a "typical" half of the surface). 1.5 means a bump of radius
  /// at most 2/3 of the typical radius of curvature; a plain sphere (every vertex = H_ref) has
  /// no region.
  double min_curvature_contrast = 1.5;
  /// Growth tolerance: a neighbour joins a seed group when its distance to the sphere fitted
  /// to the group differs from the radius by at most this fraction of the radius.
  double fit_distance_tolerance = 0.02;
  /// Growth tolerance: ... and its vertex normal is within this angle (degrees) of the sphere's
  /// outward radial direction.
  double fit_normal_tolerance_deg = 20.0;
  /// Patches smaller than this fraction of the total area are dropped (noise, single spikes).
  double min_area_fraction = 0.002;
  /// Patches larger than this fraction of the total area are not *local* structures and are
  /// dropped (cannot happen with a contrast > 1, since then H > median on the whole patch; kept
  /// as a guard for a user who lowers the contrast).
  double max_area_fraction = 0.5;

  /// Floor of H_ref in units of 1 / bounding-box diagonal, so that a mostly flat mesh (a cube:
  /// median |H| = 0) does not make every convex vertex "clearly more curved". A sphere has
  /// H = 2 sqrt(3) / diagonal = 3.46 / diagonal, so 1 is well below any round shape.
  static constexpr double REFERENCE_FLOOR = 1.0;
};

/// One selected region, as reported by select_spherical_regions.
struct RegionSummary {
  std::size_t faces = 0;         ///< number of faces
  double area = 0.0;             ///< length^2, at the given positions
  double area_fraction = 0.0;    ///< area / total area
  double mean_curvature = 0.0;   ///< area-weighted mean of the averaged H over its faces, 1/length
  double contrast = 0.0;         ///< mean_curvature / reference_mean_curvature
};

/// What select_spherical_regions measured and kept (for the CLI summary and for tuning).
struct RegionReport {
  double total_area = 0.0;                ///< length^2
  double reference_mean_curvature = 0.0;  ///< H_ref after the floor, 1/length
  std::size_t seed_vertices = 0;          ///< vertices that passed step 2
  std::size_t dropped_small = 0;          ///< patches dropped by min_area_fraction
  std::size_t dropped_large = 0;          ///< patches dropped by max_area_fraction
  std::vector<RegionSummary> regions;     ///< one per region id, in id order
};

/// Finds the local spherical regions of a closed triangle mesh (steps in the file comment).
///
/// @param mesh    triangle mesh, outward oriented (H > 0 on convex parts), no garbage.
/// @param x       vertex positions, #V by 3, row i = vertex i, any length unit (rest or deformed).
/// @param options thresholds (all scale-free).
/// @param report  optional; filled with the reference curvature and one summary per region.
/// @pre  x.rows() == number_of_vertices; options.smoothing_rings >= 0,
///       1 <= options.min_seed_vertices <= 3.
/// @return one entry per face (index = face index = input face order): the region id, or -1.
///         Ids are 0..n-1 ordered by decreasing area, ties by smallest face index.
/// @throws UsageError on a precondition failure.
std::vector<int> select_spherical_regions(const Mesh& mesh, const Positions& x, const RegionOptions& options,
                                          RegionReport* report = nullptr);

/// The same selection on the mesh's own property maps (design.md, data flow: curvature ->
/// spherical regions -> f:region): stores the curvature at x in "v:mean_curvature" and
/// "v:gaussian_curvature" (store_curvature), selects the regions from those maps, and stores the
/// ids in "f:region" (store_regions). Maps already attached are overwritten.
/// @param mesh, x, options, report as select_spherical_regions (same @pre)
/// @return the number of regions (ids 0..n-1 in f:region)
/// @throws UsageError as select_spherical_regions
std::size_t mark_spherical_regions(Mesh& mesh, const Positions& x, const RegionOptions& options,
                                   RegionReport* report = nullptr);

/// Writes the region ids into the face map "f:region" (properties.hpp), creating it if missing
/// and overwriting it otherwise.
/// @param region_of_face one entry per face, id or -1.
/// @throws UsageError if the size differs from number_of_faces.
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

/// Writes the regions of `region_of_face` in the format read_region_file reads: line r = the
/// faces with id r, ascending, separated by single spaces. Written atomically (temporary file
/// + rename).
/// @param region_of_face one entry per face, id or -1; the ids used must be 0..n-1 without a
///        gap (an empty line would be skipped on reading and shift the later ids).
/// @throws UsageError if an id in 0..max has no face, or the file cannot be written.
void write_region_file(const std::string& path, const std::vector<int>& region_of_face);

/// Display colour of a region: id >= 0 gets a saturated hue stepped by the golden angle (so
/// neighbouring ids differ strongly and no two of the first few dozen look alike); -1 is grey.
/// @return {red, green, blue}, 0..255.
std::array<unsigned char, 3> region_colour(int id);

/// Writes the regions stored on the mesh as a PLY (write_ply_atomic: ASCII, 17 significant
/// digits, vertex and face order kept, atomic) at positions x: per face `red green blue alpha`
/// (region_colour) and `int region` from "f:region"; per vertex `double mean_curvature` and
/// `double gaussian_curvature` when those maps are attached (mark_spherical_regions stores them).
/// @param x #V by 3 positions, row i = vertex i.
/// @throws UsageError when x does not match the mesh or the file cannot be written.
void write_region_ply(const std::string& path, const Mesh& mesh, const Positions& x);

}  // namespace shellcontract
