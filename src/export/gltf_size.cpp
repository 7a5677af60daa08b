// The .glb's size: its bound before the run, and the check of the true size as it is written
// (gltf_size.hpp).
#include "export/gltf_size.hpp"

#include <tiny_gltf.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <limits>
#include <streambuf>

#include "export/gltf_input_materials.hpp"
#include "export/gltf_primitives.hpp"
#include "export/gltf_vertices.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract::gltf {

namespace {

constexpr std::uint64_t GLB_LIMIT = std::numeric_limits<std::uint32_t>::max();
std::atomic<std::uint64_t> test_limit{0};

/// The ids the extras list for `face_region`: at most its largest id + 1, and at most one per
/// face.
std::uint64_t region_ids_bound(const std::vector<int>& face_region) {
  const int largest =
      face_region.empty() ? -1 : *std::max_element(face_region.begin(), face_region.end());
  return std::min<std::uint64_t>(face_region.size(), static_cast<std::uint64_t>(largest + 1));
}

/// A name's bytes in the JSON at most: a control character is escaped as \u00XX.
std::uint64_t escaped(const std::string& s) { return 6 * static_cast<std::uint64_t>(s.size()) + 2; }

/// The JSON chunk's bytes at most. Each entry is given an allowance above the most it takes with
/// 20-digit numbers and 17-digit floats: an accessor with its view (min and max of three floats
/// for POSITION), one primitive's entry for a morph target, a frame's entries in the mesh's
/// extras and weights. The names are counted escaped.
std::uint64_t json_bound(const GltfAnimation& a, std::uint64_t nk) {
  const std::uint64_t primitives = a.materials.size() + 1, targets = nk > 0 ? nk - 1 : 0;
  const std::uint64_t accessors = primitives + 4 + a.colour_fields.size() +
                                  a.frame_fields.size() * nk + 2 * targets + 2 +
                                  (a.face_region.empty() ? 0 : 1);
  std::uint64_t n = 4096;                   // asset, scene, node, animation, buffer
  n += accessors * 384;                     // accessor and bufferView
  n += primitives * (1024 + targets * 64);  // attributes, and each target's entry
  n += nk * 64;                             // frame_numbers, targetNames, weights
  n += a.frame_fields.size() * nk * 24;     // each frame's accessor in the extras
  n += 2 * escaped(a.name);                 // the node's and the mesh's
  for (const NamedVertexField& f : a.colour_fields) n += 512 + 2 * escaped(f.name);
  for (const auto& f : a.frame_fields) n += 512 + escaped(f.first);
  // The regions' entry, and each id in its `ids` (at most one per face; 8 digits and a comma).
  if (!a.face_region.empty()) n += 512 + 10 * region_ids_bound(a.face_region);
  for (const GltfMaterial& m : a.materials)
    n += 2048 + escaped(m.name) + escaped(m.image_mime_type);  // material, texture, image, sampler
  if (a.material_source) {
    const tinygltf::Model& s = *a.material_source;
    n += 4096 * (s.materials.size() + s.textures.size() + s.images.size() + s.samplers.size());
    for (const tinygltf::Material& m : s.materials) n += escaped(m.name);
    for (const tinygltf::Image& i : s.images)
      n += escaped(i.name) + escaped(i.uri) + escaped(i.mimeType);
  }
  return n;
}

std::uint32_t le32(const char* p) {
  return static_cast<std::uint32_t>(static_cast<unsigned char>(p[0])) |
         static_cast<std::uint32_t>(static_cast<unsigned char>(p[1])) << 8 |
         static_cast<std::uint32_t>(static_cast<unsigned char>(p[2])) << 16 |
         static_cast<std::uint32_t>(static_cast<unsigned char>(p[3])) << 24;
}

/// In front of the file: holds the first 20 bytes (the header and the JSON chunk's header)
/// until the JSON chunk's length is in them; with the BIN chunk's (known) that is the file's
/// true size, and one over the limit is refused before a byte reaches the file. tinygltf
/// computes the lengths as uint32 without a check: past 4 GiB it would write wrapped ones.
class SizeGuard final : public std::streambuf {
 public:
  SizeGuard(std::ostream& out, std::uint64_t bin_bytes) : out_(out), bin_(bin_bytes) {}
  std::uint64_t size() const { return size_; }  ///< 0 until known
  std::uint64_t written() const { return written_; }
  bool refused() const { return refused_; }

 protected:
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (refused_) return 0;
    std::streamsize taken = 0;
    while (held_ < 20 && taken < n) head_[held_++] = s[taken++];
    if (held_ < 20) return n;
    if (size_ == 0) {
      size_ = 20 + std::uint64_t{le32(head_ + 12)} + (bin_ > 0 ? 8 + bin_ : 0);
      if (size_ > glb_max_bytes()) {
        refused_ = true;
        return 0;
      }
      forward(head_, 20);
    }
    forward(s + taken, n - taken);
    return out_ ? n : 0;
  }
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    const char ch = traits_type::to_char_type(c);
    return xsputn(&ch, 1) == 1 ? c : traits_type::eof();
  }

 private:
  void forward(const char* s, std::streamsize n) {
    out_.write(s, n);
    written_ += static_cast<std::uint64_t>(n);
  }
  std::ostream& out_;
  std::uint64_t bin_, size_ = 0, written_ = 0;
  char head_[20] = {};
  int held_ = 0;
  bool refused_ = false;
};

[[noreturn]] void refuse(const std::string& path, std::uint64_t bytes) {
  throw UsageError("cannot write '" + path + "': the .glb would be " + size_text(bytes) + " (" +
                   std::to_string(bytes) + " bytes), over the " + size_text(glb_max_bytes()) +
                   " a .glb can hold (its lengths are 32-bit numbers); write fewer frames or "
                   "fewer fields");
}

}  // namespace

std::size_t buffer_capacity(const GltfAnimation& a, std::size_t nv, std::size_t nk) {
  const std::size_t vec3 = 12 * nv + 3, targets = nk > 0 ? nk - 1 : 0;
  return 4 * static_cast<std::size_t>(a.faces.size()) + 3 * (1 + a.materials.size()) +  // indices
         (2 + 2 * targets) * vec3 +                                      // attributes and targets
         (a.face_uv.rows() > 0 ? 8 * nv + 3 : 0) +                       // TEXCOORD_0
         4 * a.colour_fields.size() * nv + 3 * a.colour_fields.size() +  // values
         (a.colour.rows() > 0 ? 16 * nv + 3 : 0) +                       // COLOR_0
         (a.face_region.empty() ? 0 : 4 * nv + 3) +                      // _REGION
         a.frame_fields.size() * nk * (4 * nv + 3) +                     // frame fields
         4 * nk + 3 + 4 * nk * targets + 3 +                             // keys and weights
         material_bytes(a.materials) +                                   // embedded images
         source_material_bytes(a.material_source.get());                 // a glTF input's images
}

std::size_t glb_vertices(const GltfAnimation& layout) {
  if (layout.frames.empty()) return 0;
  // Split only where something splits them (a seam, a hard edge, a colour, a region's rim).
  if (layout.face_uv.rows() > 0 || layout.face_normal.rows() > 0 || layout.face_colour.rows() > 0 ||
      !layout.face_region.empty())
    return split_vertices(layout).source.size();
  return static_cast<std::size_t>(layout.frames[0].rows());
}

std::uint64_t glb_size_bound(const GltfAnimation& layout, std::size_t frames,
                             std::size_t vertices) {
  return 20 + json_bound(layout, frames) + 8 + buffer_capacity(layout, vertices, frames);
}

std::uint64_t glb_max_bytes() {
  const std::uint64_t t = test_limit.load();
  return t > 0 ? t : GLB_LIMIT;
}

void set_glb_max_bytes_for_test(std::uint64_t bytes) { test_limit.store(bytes); }

std::size_t write_glb(const std::string& path, const tinygltf::Model& model, std::ostream& out) {
  const std::uint64_t bin = model.buffers.empty() ? 0 : model.buffers[0].data.size();
  // Refused at once when the buffer alone is too large: tinygltf's serializing would copy it.
  if (28 + bin > glb_max_bytes()) refuse(path, 28 + bin);
  SizeGuard guard(out, bin);
  std::ostream guarded(&guard);
  tinygltf::TinyGLTF writer;
  const bool ok = writer.WriteGltfSceneToStream(&model, guarded, false, true);
  if (guard.refused()) refuse(path, guard.size());
  if (!ok || !guarded || !out)
    throw UsageError("cannot write '" + path + "': serializing the glTF failed");
  // A JSON chunk of 4 GiB would have wrapped its own length: the bytes written tell.
  if (guard.written() != guard.size())
    throw UsageError("cannot write '" + path + "': the .glb's lengths do not match its " +
                     std::to_string(guard.written()) + " bytes");
  return static_cast<std::size_t>(guard.written());
}

std::string size_text(std::uint64_t bytes) {
  const char* units[] = {"KiB", "MiB", "GiB", "TiB"};
  if (bytes < 1024) return std::to_string(bytes) + " bytes";
  double v = static_cast<double>(bytes) / 1024.0;
  int u = 0;
  while (v >= 1024.0 && u < 3) {
    v /= 1024.0;
    ++u;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, v < 10.0 ? "%.1f %s" : "%.0f %s", v, units[u]);
  return buf;
}

}  // namespace shellcontract::gltf
