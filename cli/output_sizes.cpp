#include "output_sizes.hpp"

#include <sys/stat.h>
#include <sys/statvfs.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <map>
#include <vector>

#include "command_line.hpp"
#include "export/gltf_size.hpp"
#include "export_observer.hpp"
#include "mesh/formats.hpp"
#include "mesh/output_check.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract::cli {

namespace {

namespace fs = std::filesystem;

std::atomic<std::uint64_t> test_big_output{0};

std::uint64_t digits(std::uint64_t n) {
  std::uint64_t d = 1;
  while (n >= 10) {
    n /= 10;
    ++d;
  }
  return d;
}

/// The nearest existing folder that will hold `path` (a file, or with `is_folder` a folder that
/// may not exist yet).
std::string holding_folder(const std::string& path, bool is_folder) {
  fs::path p = fs::path(path).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  if (!is_folder) p = p.parent_path();
  struct stat st {};
  while (!p.empty() && ::stat(p.c_str(), &st) != 0) p = p.parent_path();
  return p.empty() ? std::string(".") : p.string();
}

}  // namespace

std::uint64_t frame_file_estimate(const std::string& ext, std::uint64_t vertices,
                                  std::uint64_t faces, std::uint64_t document_bytes) {
  // A coordinate of 17 significant digits takes at most 24 characters ("-1.2345678901234567e-100");
  // a face's index at most the digits of the vertex count.
  const std::uint64_t index = digits(vertices) + 2;
  const MeshFormat* format = find_mesh_format(ext);
  // STL (no vertex numbers): a facet's normal, three vertices and five keyword lines.
  if (format && !format->indexed_vertices)
    return 128 + faces * (3 * 24 + 4 * (3 * 24 + 16) + 64) + document_bytes;
  return 256 + vertices * (3 * 25 + 4) + faces * (4 + 3 * index) + document_bytes;
}

std::uint64_t fields_estimate(std::uint64_t vertices, std::uint64_t faces) {
  // Per vertex: the position, a colour and four float fields; per face its three indices.
  return 2 * (1024 + vertices * (3 * 25 + 12 + 4 * 16) + faces * (4 + 3 * (digits(vertices) + 2)));
}

void plan_gltf_size(OutputSizePlan& plan, const GltfAnimation& layout) {
  const std::size_t nv = gltf::glb_vertices(layout);
  const auto bound = [&](int every) {
    return gltf::glb_size_bound(
        layout, static_cast<std::size_t>(FrameExporter::kept_frames(plan.frames, every)), nv);
  };
  plan.gltf_vertices = nv;
  plan.gltf_bytes = bound(plan.every);
  plan.gltf_fit_every = 0;
  if (plan.gltf_bytes <= gltf::glb_max_bytes()) {
    plan.gltf_fit_every = plan.every;
    return;
  }
  // The least N that fits: the bound falls as N grows (fewer kept frames); N = frames keeps two.
  int lo = plan.every, hi = std::max(plan.frames, 1);
  if (bound(hi) > gltf::glb_max_bytes()) return;
  while (hi - lo > 1) {
    const int mid = lo + (hi - lo) / 2;
    (bound(mid) <= gltf::glb_max_bytes() ? hi : lo) = mid;
  }
  plan.gltf_fit_every = hi;
}

void check_output_sizes(const OutputSizePlan& plan, std::ostream& warnings) {
  const int kept = FrameExporter::kept_frames(plan.frames, plan.every);
  if (!plan.gltf.empty() && plan.gltf_bytes > gltf::glb_max_bytes()) {
    std::string change =
        plan.gltf_fit_every > 0
            ? "keep fewer frames: --export-every " + std::to_string(plan.gltf_fit_every) +
                  " or more (" +
                  std::to_string(FrameExporter::kept_frames(plan.frames, plan.gltf_fit_every)) +
                  " frames), or fewer frames (-n)"
            : "even two frames of this mesh do not fit: write its frames with --export-dir instead";
    throw UsageError("--gltf " + quoted_path(plan.gltf) + ": the .glb would be up to " +
                     gltf::size_text(plan.gltf_bytes) + " (" + std::to_string(plan.gltf_bytes) +
                     " bytes: " + std::to_string(kept) + " kept frames of " +
                     std::to_string(plan.gltf_vertices) + " vertices), over the " +
                     std::to_string(gltf::glb_max_bytes()) +
                     " bytes a .glb can hold (its lengths are 32-bit numbers); " + change);
  }
  // Each output's bytes by the folder that takes it.
  struct Part {
    std::string option, folder;
    std::uint64_t bytes;
  };
  std::vector<Part> parts;
  if (!plan.gltf.empty())
    parts.push_back({"--gltf", holding_folder(plan.gltf, false), plan.gltf_bytes});
  if (!plan.frames_dir.empty())
    parts.push_back({"--export-dir", holding_folder(plan.frames_dir, true),
                     plan.frame_bytes * static_cast<std::uint64_t>(kept)});
  if (!plan.fields.empty())
    parts.push_back({"--fields", holding_folder(plan.fields, false), plan.fields_bytes});
  std::uint64_t total = 0;
  std::string list;
  for (const Part& p : parts) {
    total += p.bytes;
    list += (list.empty() ? "" : ", ") + p.option + " " + gltf::size_text(p.bytes);
  }
  if (total > big_output_bytes())
    warnings << "warning: the outputs will take up to about " << gltf::size_text(total) << " ("
             << list << ")"
             << (plan.gltf.empty() && plan.frames_dir.empty()
                     ? std::string()
                     : "; " + std::to_string(kept) + " kept frames: --export-every keeps fewer")
             << '\n';
  // Free space per file system, where statvfs answers (a warning: the estimate is a bound).
  std::map<dev_t, std::pair<std::string, std::uint64_t>> by_device;
  for (const Part& p : parts) {
    struct stat st {};
    if (::stat(p.folder.c_str(), &st) != 0) continue;
    auto& d = by_device[st.st_dev];
    if (d.first.empty()) d.first = p.folder;
    d.second += p.bytes;
  }
  for (const auto& [device, d] : by_device) {
    struct statvfs vfs {};
    if (::statvfs(d.first.c_str(), &vfs) != 0) continue;
    const std::uint64_t free_bytes =
        static_cast<std::uint64_t>(vfs.f_bavail) * static_cast<std::uint64_t>(vfs.f_frsize);
    if (d.second > free_bytes)
      warnings << "warning: the outputs in " << quoted_path(d.first) << " may take up to about "
               << gltf::size_text(d.second) << ", and its file system has "
               << gltf::size_text(free_bytes) << " free\n";
  }
}

std::uint64_t big_output_bytes() {
  const std::uint64_t t = test_big_output.load();
  return t > 0 ? t : BIG_OUTPUT_BYTES;
}

void set_big_output_bytes_for_test(std::uint64_t bytes) { test_big_output.store(bytes); }

void check_run_output_sizes(const FrameExporter& exporter, const ExportRequest& exports,
                            const Mesh& mesh, const MeshDocument* document,
                            const std::string& input, const std::string& fields_prefix, int frames,
                            std::ostream& warnings) {
  OutputSizePlan sizes;
  sizes.frames = frames;
  sizes.every = exporter.every();
  if (!exports.gltf.empty()) {
    sizes.gltf = exports.gltf;
    plan_gltf_size(sizes, exporter.gltf_layout());
  }
  if (!exports.dir.empty()) {
    std::error_code ec;  // a frame written through the document carries its other lines
    const std::uintmax_t input_bytes = fs::file_size(input, ec);
    sizes.frames_dir = exports.dir;
    sizes.frame_bytes =
        frame_file_estimate(exports.ext, input_vertex_count(mesh), mesh.number_of_faces(),
                            document && document->format() == exports.ext && !ec ? input_bytes : 0);
  }
  if (!fields_prefix.empty()) {
    sizes.fields = fields_prefix;
    sizes.fields_bytes = fields_estimate(mesh.number_of_vertices(), mesh.number_of_faces());
  }
  check_output_sizes(sizes, warnings);
}

}  // namespace shellcontract::cli
