// The CLI's frame export (README "See the contraction"): every N-th frame of a run, and the first
// and the last, as mesh files written on a background thread and/or as one animated glTF.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "export/frame_sequence_writer.hpp"
#include "geometry/curvature.hpp"
#include "shellcontract/export.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/regions.hpp"
#include "shellcontract/run.hpp"
#include "sim/fields.hpp"
#include "sim/frame_access.hpp"
#include "sim/simulator.hpp"

namespace shellcontract::cli {

/// What --export-every, --export-dir and --gltf asked for.
struct ExportRequest {
  int every = 0;     ///< every N-th frame; 0 = the default for --gltf alone (see exporter)
  std::string dir;   ///< frame files' folder; empty = no frame files
  std::string name;  ///< frame files' stem (the output's stem)
  std::string ext;   ///< frame files' format (the output's extension)
  std::string gltf;  ///< animated .glb; empty = none
  double seconds_per_frame = 1.0 / 24.0;
  /// --export-failure stop: a frame file that cannot be written ends the run (its result and
  /// the other outputs are still written); otherwise only the export stops.
  bool stop_run_on_failure = false;
};

/// Exports frames as the run shows them. Only reads positions, so the run is the same with or
/// without it (test: byte-identical result).
class FrameExporter final : public RunObserver {
 public:
  FrameExporter(ExportRequest request, const Mesh& mesh, int frames)
      : request_(std::move(request)), mesh_(mesh) {
    // --gltf alone keeps about 100 frames, enough to play smoothly, few enough for a small file.
    if (request_.every <= 0) request_.every = std::max(1, (frames + 99) / 100);
    max_frame_ = frames;
  }

  /// The frames a run of `frames` frames keeps with every `every`-th: frame 0, every N-th and
  /// the last (fewer when the run stops early).
  static int kept_frames(int frames, int every) {
    return frames / every + 1 + (frames % every != 0 ? 1 : 0);
  }
  /// What the .glb holds before the run (gltf::glb_size_bound's layout): frame 0's rows, the
  /// faces, the input's attributes and materials, and the fields by name.
  GltfAnimation gltf_layout() const {
    GltfAnimation layout = gltf_;
    layout.faces = faces_array(mesh_);
    layout.frames = {Positions::Zero(static_cast<Eigen::Index>(mesh_.number_of_vertices()), 3)};
    layout.frame_fields = {{FRAME_FIELD, {}}};
    layout.colour_fields.clear();
    for (const char* name : COLOUR_FIELDS) layout.colour_fields.push_back({name, {}});
    // The regions are selected after this (--regions auto): their attribute and entry are
    // counted, the copies of their rims' vertices cannot be (the writer's own check of the
    // file's true size covers them).
    if (regions_expected_) layout.face_region.assign(mesh_.number_of_faces(), 0);
    return layout;
  }

  void started(const FrameView& view) override {
    // The frames are written as -o is: through the input's document when it is of their format.
    if (!request_.dir.empty())
      writer_.emplace(request_.dir, request_.name, request_.ext, mesh_, max_frame_,
                      FrameSequenceWriter::DEFAULT_QUEUE_CAPACITY,
                      document_ && document_->format() == request_.ext ? document_ : nullptr);
    if (!request_.gltf.empty()) {
      gltf_.faces = faces_array(mesh_);
      // Each face's region (the run's f:region map, on the run's faces in the input's order),
      // so that the .glb shows which faces were contracted; none without regions.
      if (view.regions() > 0) gltf_.face_region = stored_regions(simulator_of(view).rest_mesh());
    }
    take(0, view);
  }
  void frame(const FrameView& view, const FrameMetrics& m) override {
    if (m.frame % request_.every == 0 || view.last()) take(m.frame, view);
  }
  /// Polled after every step: with --export-failure stop, a failed frame file ends the run.
  bool cancelled() override {
    return request_.stop_run_on_failure && writer_ && writer_->failed();
  }
  void finished(const FrameView& view, const RunResult&) override {
    if (last_ != view.frame()) take(view.frame(), view);  // a run that stopped early
    // A failed frame file (a full disk) stops the export, not the run: the result, the log and
    // the summary are still written, and the run's end names the failure.
    if (writer_) {
      try {
        writer_->finish();
      } catch (const std::exception& e) {
        export_error_ = e.what();
      }
    }
    if (!request_.gltf.empty()) {
      const auto start = std::chrono::steady_clock::now();
      const VertexFields f = compute_vertex_fields(simulator_of(view));
      gltf_.colour_fields = {{COLOUR_FIELDS[0], f.mean_curvature},
                             {COLOUR_FIELDS[1], f.gaussian_curvature},
                             {COLOUR_FIELDS[2], f.pressure},
                             {COLOUR_FIELDS[3], f.energy_density}};
      gltf_.colour_frame = view.frame();  // the fields are this frame's, not every frame's
      gltf_.seconds_per_frame = request_.seconds_per_frame;
      gltf_seconds_ =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
  }

  /// The input kept whole (read_mesh_document, matching the mesh), for frame files of its format.
  void set_document(std::shared_ptr<const MeshDocument> document) { document_ = std::move(document); }

  /// The input's texture coordinates, for the glTF's TEXCOORD_0; empty: none.
  void set_texcoords(const CornerTexcoords& t) {
    if (t.empty()) return;
    gltf_.uv.resize(static_cast<Eigen::Index>(t.uv.size()), 2);
    for (std::size_t i = 0; i < t.uv.size(); ++i)
      gltf_.uv.row(static_cast<Eigen::Index>(i)) << t.uv[i][0], t.uv[i][1];
    gltf_.face_uv.resize(static_cast<Eigen::Index>(t.face_uv.size()), 3);
    for (std::size_t f = 0; f < t.face_uv.size(); ++f)
      for (int k = 0; k < 3; ++k)
        gltf_.face_uv(static_cast<Eigen::Index>(f), k) = static_cast<int>(t.face_uv[f][static_cast<std::size_t>(k)]);
  }

  /// The input's vertex colours, for the glTF's COLOR_0; empty: none.
  void set_colours(const CornerColours& c) {
    if (c.empty()) return;
    gltf_.colour.resize(static_cast<Eigen::Index>(c.rgba.size()), 4);
    for (std::size_t i = 0; i < c.rgba.size(); ++i)
      for (int k = 0; k < 4; ++k)
        gltf_.colour(static_cast<Eigen::Index>(i), k) = c.rgba[i][static_cast<std::size_t>(k)];
    gltf_.colour_channels = c.channels;
    gltf_.face_colour.resize(static_cast<Eigen::Index>(c.face_colour.size()), 3);
    for (std::size_t f = 0; f < c.face_colour.size(); ++f)
      for (int k = 0; k < 3; ++k)
        gltf_.face_colour(static_cast<Eigen::Index>(f), k) =
            static_cast<int>(c.face_colour[f][static_cast<std::size_t>(k)]);
  }

  /// The input's normal groups, for the glTF's hard edges; empty: none (smooth normals).
  void set_normal_groups(const CornerNormalGroups& g) {
    if (g.empty()) return;
    gltf_.face_normal.resize(static_cast<Eigen::Index>(g.face_group.size()), 3);
    for (std::size_t f = 0; f < g.face_group.size(); ++f)
      for (int k = 0; k < 3; ++k)
        gltf_.face_normal(static_cast<Eigen::Index>(f), k) =
            static_cast<int>(g.face_group[f][static_cast<std::size_t>(k)]);
    gltf_.face_polygon.assign(g.face_polygon.begin(), g.face_polygon.end());
  }

  /// Whether the run has regions (a region source given, or --regions auto implied): the
  /// .glb's size bound (gltf_layout) then counts their attribute.
  void expect_regions(bool expected) { regions_expected_ = expected; }

  /// The glTF's node and mesh name (the input's stem).
  void set_gltf_name(std::string name) { gltf_.name = std::move(name); }
  /// The glTF's materials and each face's (gltf_materials: the OBJ's .mtl, the PLY's
  /// TextureFile images); empty: none.
  void set_materials(std::vector<GltfMaterial> materials, std::vector<int> face_material,
                     std::shared_ptr<const tinygltf::Model> source) {
    gltf_.materials = std::move(materials);
    gltf_.face_material = std::move(face_material);
    gltf_.material_source = std::move(source);
  }

  /// Writes the .glb of --gltf, after the run: the simulator's memory is free by then (written
  /// from finished(), the file raised a large mesh's peak far above its run's; lab/history.md).
  void write_gltf() {
    if (request_.gltf.empty() || gltf_.frames.empty()) return;
    const auto start = std::chrono::steady_clock::now();
    gltf_bytes_ = write_gltf_animation(request_.gltf, std::move(gltf_)).bytes;
    gltf_ = GltfAnimation{};
    gltf_seconds_ +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  /// Export costs for the summary: frame files (counts and both threads' time) and the glTF.
  ExportStats frame_stats() const { return writer_ ? writer_->stats() : ExportStats{}; }
  std::size_t gltf_bytes() const { return gltf_bytes_; }
  double gltf_seconds() const { return gltf_seconds_; }
  double gltf_copy_seconds() const { return gltf_copy_seconds_; }
  int every() const { return request_.every; }
  /// Why the frame files stopped being written; empty when they all were.
  const std::string& export_error() const { return export_error_; }
  /// The warnings of writing the frame files (FrameSequenceWriter::warnings), once each.
  std::vector<std::string> frame_warnings() const { return writer_ ? writer_->warnings() : std::vector<std::string>{}; }

 private:
  // The .glb's fields: the end's four, and each kept frame's mean curvature.
  static constexpr const char* COLOUR_FIELDS[4] = {"mean_curvature", "gaussian_curvature",
                                                   "pressure", "energy_density"};
  static constexpr const char* FRAME_FIELD = "mean_curvature";

  void take(int frame, const FrameView& view) {
    last_ = frame;
    if (!writer_ && request_.gltf.empty()) return;
    const Positions x = view.positions();
    if (writer_) writer_->write(frame, x);
    if (!request_.gltf.empty()) {
      const auto start = std::chrono::steady_clock::now();
      // Each kept frame's own mean curvature (the default colour field, computed as
      // compute_vertex_fields does), so that a viewer colours every frame with its values, not
      // the end's.
      if (gltf_.frame_fields.empty()) gltf_.frame_fields.push_back({FRAME_FIELD, {}});
      auto mean =
          input_unit_mean_curvature(simulator_of(view), view.normalized_positions()).cast<float>().eval();
      // A frame's three entries all or none: memory that runs out here (std::bad_alloc, which
      // ends the run with its last good state) must leave lists of one length, from which the
      // glTF is still written after the run.
      auto& means = gltf_.frame_fields[0].second;
      gltf_.frame_numbers.push_back(frame);
      try {
        gltf_.frames.push_back(x);
      } catch (...) {
        gltf_.frame_numbers.pop_back();
        throw;
      }
      try {
        means.push_back(std::move(mean));
      } catch (...) {
        gltf_.frames.pop_back();
        gltf_.frame_numbers.pop_back();
        throw;
      }
      gltf_copy_seconds_ +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
  }

  ExportRequest request_;
  const Mesh& mesh_;
  std::shared_ptr<const MeshDocument> document_;
  int max_frame_ = 0;
  int last_ = -1;
  bool regions_expected_ = false;
  std::optional<FrameSequenceWriter> writer_;
  GltfAnimation gltf_;
  std::size_t gltf_bytes_ = 0;
  double gltf_seconds_ = 0.0, gltf_copy_seconds_ = 0.0;
  std::string export_error_;
};

}  // namespace shellcontract::cli
