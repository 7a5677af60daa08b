// The sizes of a run's large outputs (--gltf, the frames of --export-dir, --fields), estimated
// before the run (docs/design/export.md, "Size"): a .glb over the 4 GiB its 32-bit lengths can
// hold is refused, and outputs that will be very large, or larger than the free space of their
// file system, are warned about before the run spends its time.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>

#include "shellcontract/export.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract::cli {

/// The warning threshold of the outputs' estimated total: 1 GiB, far above a default-length run of
/// the paper's meshes (docs/design/export.md, "Size"); above it a viewer or Blender holds the whole
/// .glb in memory and takes tens of seconds to load it, and a run's frames fill disks: a size the
/// user should know before the run, not after.
inline constexpr std::uint64_t BIG_OUTPUT_BYTES = std::uint64_t{1} << 30;

/// What a run will write that grows with the mesh and the kept frames.
struct OutputSizePlan {
  int frames = 0;                   ///< the run's frames (-n)
  int every = 1;                    ///< --export-every, resolved
  std::string gltf;                 ///< --gltf; empty: none
  std::uint64_t gltf_bytes = 0;     ///< its bound (gltf::glb_size_bound)
  std::uint64_t gltf_vertices = 0;  ///< the .glb's vertices (gltf::glb_vertices)
  int gltf_fit_every = 0;          ///< the least --export-every whose .glb fits; 0: none (gltf_fit)
  std::string frames_dir;          ///< --export-dir; empty: none
  std::uint64_t frame_bytes = 0;   ///< one frame file's estimate (frame_file_estimate)
  std::string fields;              ///< --fields' prefix; empty: none
  std::uint64_t fields_bytes = 0;  ///< both files' estimate (fields_estimate)
};

/// One frame file's bytes at most, about: `vertices` and `faces` as the writers print them
/// (coordinates of 17 significant digits), plus `document_bytes` (the input file's size) for a
/// frame written through the input's document, which carries its other lines along.
std::uint64_t frame_file_estimate(const std::string& ext, std::uint64_t vertices,
                                  std::uint64_t faces, std::uint64_t document_bytes);

/// The two PLY files of --fields: positions, a colour and four fields per vertex.
std::uint64_t fields_estimate(std::uint64_t vertices, std::uint64_t faces);

/// The --gltf entries of `plan` (frames and every already set) for the .glb of `layout`
/// (FrameExporter::gltf_layout).
void plan_gltf_size(OutputSizePlan& plan, const GltfAnimation& layout);

/// Before the run. A --gltf whose bound is over gltf::glb_max_bytes() is refused, naming the
/// bound and what to change; otherwise a line on `warnings` when the total is over
/// big_output_bytes() and one per file system that has less free space (statvfs) than the
/// outputs it takes.
/// @throws UsageError (exit code 1)
void check_output_sizes(const OutputSizePlan& plan, std::ostream& warnings);

class FrameExporter;
struct ExportRequest;

/// check_output_sizes on the plan of a run's outputs: the .glb of `exporter` (its layout), the
/// frames of `exports`, the files of --fields (`fields_prefix`; empty: none), for `mesh` read
/// from `input` (its `document`, null if none, writes the frames of its format).
/// @throws UsageError (exit code 1)
void check_run_output_sizes(const FrameExporter& exporter, const ExportRequest& exports,
                            const Mesh& mesh, const MeshDocument* document,
                            const std::string& input, const std::string& fields_prefix, int frames,
                            std::ostream& warnings);

/// BIG_OUTPUT_BYTES, or the test hook's.
std::uint64_t big_output_bytes();
/// Test hook: a lower threshold (0 restores BIG_OUTPUT_BYTES).
void set_big_output_bytes_for_test(std::uint64_t bytes);

}  // namespace shellcontract::cli
