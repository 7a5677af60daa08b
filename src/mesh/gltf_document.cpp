// A glTF input as a document (docs/design/attributes.md, "glTF"): the parsed file, written back
// with each vertex's new position (and, where the file has them, new normals); everything else
// (texture coordinates, materials, textures, nodes, names, extras) is the input's JSON as it was
// (gltf_json.hpp: tinygltf's writer alone does not round-trip it).
// Positions are stored in the primitive's node space, so the node transforms stay as they were;
// a mesh drawn by several nodes gets one copy of its positions per node (gltf_instances.hpp).
#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "core/classic_locale.hpp"
#include "mesh/float32_positions.hpp"
#include "mesh/gltf_instances.hpp"
#include "mesh/gltf_json.hpp"
#include "mesh/gltf_model.hpp"
#include "mesh/gltf_written_bytes.hpp"
#include "mesh/normal_groups.hpp"
#include "mesh/seam_weld.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

class GltfDocument final : public MeshDocument {
 public:
  GltfDocument(const std::string& path, const std::string& bytes, bool binary)
      : binary_(binary), path_(path) {
    file_name_ = path;
    // The parse is read_input_mesh's (the same soup, so simulation vertex i is soup vertex i).
    model_ = gltf::load_model(path, bytes);
    input_json_ = gltf::json_text(bytes);
    soup_ = gltf::scene_soup(path, model_, bytes.size(), &world_);
    vertex_count_ = soup_.points.size();
    polygon_start_.reserve(soup_.faces.size() + 1);
    polygon_start_.push_back(0);
    for (const auto& f : soup_.faces) {
      corner_vertex_.insert(corner_vertex_.end(), f.begin(), f.end());
      polygon_start_.push_back(corner_vertex_.size());
    }
    for (std::size_t d = 0; d < soup_.drawn.size(); ++d) {
      const tinygltf::Primitive& p = primitive(d);
      const int pos = p.attributes.at("POSITION");
      // New positions are brought back into node space through the inverse transform.
      to_local_.push_back(world_[d].inverse());
      if (!(world_[d].topLeftCorner<3, 3>().determinant() != 0.0) || !to_local_.back().allFinite())
        throw InputError(path + ": not writable with new positions: node " +
                         std::to_string(soup_.drawn[d].node) +
                         "'s world transform has no inverse (a scale of 0?)");
      const std::string name = "mesh " + std::to_string(soup_.drawn[d].mesh) + " primitive " +
                               std::to_string(soup_.drawn[d].primitive);
      positions_.push_back({gltf::element_view(path, model_, pos, name + " POSITION", 12), pos});
      const std::size_t count = positions_.back().view.count;
      normals_.push_back(float_attribute(path, p, "NORMAL", TINYGLTF_TYPE_VEC3, 12, name, count));
      texcoords_.push_back(
          float_attribute(path, p, "TEXCOORD_0", TINYGLTF_TYPE_VEC2, 8, name, count));
    }
    gltf::check_written_bytes_alone(path, model_, soup_, positions_, normals_);
    read_texcoords();
    read_colours(path);
    read_normals();
    read_materials(path);
    // Each drawing of an instanced mesh holds its own moved copy (gltf_instances.hpp).
    std::vector<bool> written_normal;
    for (const gltf::Written& n : normals_) written_normal.push_back(n.accessor >= 0);
    const auto written = gltf::realize_instances(path, model_, soup_, written_normal);
    for (std::size_t d = 0; d < written.size(); ++d) {
      const std::string name = "mesh " + std::to_string(soup_.drawn[d].mesh) + " primitive " +
                               std::to_string(soup_.drawn[d].primitive);
      if (written[d].position != positions_[d].accessor)
        positions_[d] = {
            gltf::element_view(path, model_, written[d].position, name + " POSITION", 12),
            written[d].position};
      if (written[d].normal != normals_[d].accessor)
        normals_[d] = {gltf::element_view(path, model_, written[d].normal, name + " NORMAL", 12),
                       written[d].normal};
    }
  }

  std::string format() const override { return binary_ ? "glb" : "gltf"; }

  /// By the normal groups of write_normals: copies with their own normals (a flat side, a hard
  /// edge) are groups of their own; a vertex of a primitive without float normals has none.
  std::vector<long long> corner_normal_groups(const Mesh& mesh) const override {
    return soup::welded_corner_groups(input_vertex_map(mesh), input_normal_, corner_vertex_);
  }

  std::string text(const Positions& x) const override { return text_with(input_json_, x); }

  /// text(x) with each image's relative URI naming the same file from the output's folder, as
  /// an OBJ's mtllib paths are rewritten (gltf_json.hpp, relocate_image_uris); frames of
  /// --export-dir and the result alike.
  std::string text_for(const std::string& output_path, const Positions& x,
                       std::vector<std::string>* warnings) const override {
    return text_with(gltf::relocate_image_uris(input_json_, path_, output_path, warnings), x);
  }

  /// The float32 spacing at each drawn primitive's largest node-space coordinate of x, mapped to
  /// world units by the node's transform (its largest singular value), the largest of them.
  double float32_spacing(const Positions& x) const {
    std::vector<double> largest(soup_.drawn.size(), 0.0);
    for (std::size_t v = 0; v < vertex_count_; ++v) {
      const std::size_t d = soup_.sources[v].drawn;
      largest[d] = std::max(largest[d], local(x, v).cwiseAbs().maxCoeff());
    }
    double spacing = 0.0;
    for (std::size_t d = 0; d < largest.size(); ++d) {
      const Eigen::Matrix3d a = world_[d].topLeftCorner<3, 3>();
      const double stretch = Eigen::JacobiSVD<Eigen::Matrix3d>(a).singularValues()(0);
      spacing = std::max(spacing, shellcontract::float32_spacing(largest[d]) * stretch);
    }
    return spacing;
  }
  /// x as the file holds them read back: in node space, rounded to float32, to world as the
  /// reader maps them (gltf_reader.cpp).
  Positions rounded(const Positions& x) const {
    Positions out(x.rows(), 3);
    for (std::size_t v = 0; v < vertex_count_; ++v) {
      const Eigen::Vector3d stored = local(x, v).cast<float>().cast<double>();
      out.row(static_cast<Eigen::Index>(v)) =
          (world_[soup_.sources[v].drawn] * stored.homogeneous()).head<3>().transpose();
    }
    return out;
  }

 private:
  /// The file with positions x, its JSON `json` (the input's, or one with other image URIs).
  std::string text_with(const std::string& json, const Positions& x) const {
    if (static_cast<std::size_t>(x.rows()) != vertex_count_ || x.cols() != 3)
      throw std::invalid_argument("GltfDocument::text: " + std::to_string(x.rows()) +
                                  " positions for " + std::to_string(vertex_count_) + " vertices");
    if (!x.allFinite())
      throw std::invalid_argument("GltfDocument::text: a coordinate is not finite");
    tinygltf::Model m = model_;
    for (std::size_t v = 0; v < vertex_count_; ++v) {
      const auto& s = soup_.sources[v];
      const Eigen::Vector3d l = local(x, v);
      put_floats(m, positions_[s.drawn].view, s.element, {l[0], l[1], l[2]});
    }
    write_normals(m, x);
    // The images are written as the input's JSON has them (gltf_json.hpp): tinygltf's JSON of
    // them is not used, so it is not made (a data-URI image would be encoded again).
    m.images.clear();
    for (const gltf::Written& w : positions_) update_bounds(m, w);
    ClassicOStringStream out;
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&m, out, !binary_, binary_))
      throw std::runtime_error("GltfDocument::text: tinygltf could not serialize the model");
    std::vector<int> bounded;
    for (const gltf::Written& w : positions_) bounded.push_back(w.accessor);
    return gltf::restore_input_json(json, out.str(), binary_, bounded);
  }

  /// Vertex v's position x in its primitive's node space, as text_with writes it.
  Eigen::Vector3d local(const Positions& x, std::size_t v) const {
    const auto i = static_cast<Eigen::Index>(v);
    return (to_local_[soup_.sources[v].drawn] * Eigen::Vector4d(x(i, 0), x(i, 1), x(i, 2), 1.0))
        .head<3>();
  }

  const tinygltf::Primitive& primitive(std::size_t d) const {
    return model_.meshes[soup_.drawn[d].mesh].primitives[soup_.drawn[d].primitive];
  }

  /// The primitive's float attribute of `type`, checked; none (accessor -1) when it has none or
  /// one of another kind (a quantized normal or texture coordinate is kept as it is). One whose
  /// count is not POSITION's (the spec says they are equal) is refused: its elements are read
  /// and written by POSITION's element numbers.
  gltf::Written float_attribute(const std::string& path, const tinygltf::Primitive& p,
                                const char* name, int type, std::size_t size,
                                const std::string& prim, std::size_t count) const {
    const auto it = p.attributes.find(name);
    if (it == p.attributes.end() || it->second < 0 ||
        static_cast<std::size_t>(it->second) >= model_.accessors.size())
      return {};
    const tinygltf::Accessor& a = model_.accessors[static_cast<std::size_t>(it->second)];
    if (a.type != type || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || a.sparse.isSparse)
      return {};
    const gltf::ElementView view =
        gltf::element_view(path, model_, it->second, prim + " " + name, size);
    if (view.count != count)
      throw InputError(path + ": attribute count mismatch: " + prim + " " + name + " (accessor " +
                       std::to_string(it->second) + ") has " + std::to_string(view.count) +
                       " elements, POSITION " + std::to_string(count));
    return {view, it->second};
  }

  /// Texture coordinates for the --gltf animation: one per vertex (its primitive's TEXCOORD_0),
  /// v flipped to the OBJ convention that CornerTexcoords holds (the exporter flips it back).
  void read_texcoords() {
    for (const gltf::Written& t : texcoords_)
      if (t.accessor < 0) return;  // a primitive without: none at all (MeshDocument::texcoords)
    uv_.resize(vertex_count_);
    for (std::size_t v = 0; v < vertex_count_; ++v) {
      const auto& s = soup_.sources[v];
      float f[2];
      std::memcpy(f, texcoords_[s.drawn].view.at(model_, s.element), sizeof f);
      uv_[v] = {f[0], 1.0 - static_cast<double>(f[1])};
    }
    corner_uv_.assign(corner_vertex_.begin(), corner_vertex_.end());
  }

  std::string vertex_place(std::size_t v) const override {
    const auto& s = soup_.sources.at(v);
    return "mesh " + std::to_string(soup_.drawn[s.drawn].mesh) + " primitive " +
           std::to_string(soup_.drawn[s.drawn].primitive) + " vertex " + std::to_string(s.element);
  }
  std::string uv_place(std::size_t uv) const override {
    return vertex_place(uv);
  }  // one per vertex

  /// Vertex colours for the --gltf animation: each vertex's primitive's COLOR_0 (float, or
  /// normalized unsigned byte or short; RGB or RGBA), white where a primitive has none (glTF's
  /// meaning of no COLOR_0). None when no primitive has one.
  void read_colours(const std::string& path) {
    std::vector<gltf::ElementView> views(soup_.drawn.size());
    std::vector<int> type(soup_.drawn.size(), -1), columns(soup_.drawn.size(), 0);
    bool any = false;
    for (std::size_t d = 0; d < soup_.drawn.size(); ++d) {
      const tinygltf::Primitive& p = primitive(d);
      const auto it = p.attributes.find("COLOR_0");
      if (it == p.attributes.end() || it->second < 0 ||
          static_cast<std::size_t>(it->second) >= model_.accessors.size())
        continue;
      const tinygltf::Accessor& a = model_.accessors[static_cast<std::size_t>(it->second)];
      const int n = a.type == TINYGLTF_TYPE_VEC3 ? 3 : a.type == TINYGLTF_TYPE_VEC4 ? 4 : 0;
      const std::size_t size = a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT            ? 4
                               : a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                               : a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE  ? 1
                                                                                           : 0;
      if (n == 0 || size == 0 || a.sparse.isSparse) continue;  // not a colour glTF allows
      const std::string name = "mesh " + std::to_string(soup_.drawn[d].mesh) + " primitive " +
                               std::to_string(soup_.drawn[d].primitive) + " COLOR_0";
      views[d] =
          gltf::element_view(path, model_, it->second, name, size * static_cast<std::size_t>(n));
      if (views[d].count != positions_[d].view.count)
        throw InputError(path + ": attribute count mismatch: " + name + " (accessor " +
                         std::to_string(it->second) + ") has " + std::to_string(views[d].count) +
                         " elements, POSITION " + std::to_string(positions_[d].view.count));
      type[d] = a.componentType;
      columns[d] = n;
      any = true;
      if (n == 4) colour_channels_ = 4;
    }
    if (!any) return;
    if (colour_channels_ == 0) colour_channels_ = 3;
    colour_.assign(vertex_count_, {1.0, 1.0, 1.0, 1.0});
    for (std::size_t v = 0; v < vertex_count_; ++v) {
      const auto& s = soup_.sources[v];
      if (type[s.drawn] < 0) continue;
      const unsigned char* b = views[s.drawn].at(model_, s.element);
      for (int c = 0; c < columns[s.drawn]; ++c) {
        double value = 0.0;
        if (type[s.drawn] == TINYGLTF_COMPONENT_TYPE_FLOAT) {
          float f;
          std::memcpy(&f, b + 4 * c, 4);
          value = f;
        } else if (type[s.drawn] == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
          std::uint16_t u;
          std::memcpy(&u, b + 2 * c, 2);
          value = u / 65535.0;
        } else {
          value = b[c] / 255.0;
        }
        colour_[v][static_cast<std::size_t>(c)] = value;
      }
    }
  }

  /// The --gltf animation's materials: the model's own, and per polygon its primitive's.
  void read_materials(const std::string& path) {
    if (model_.materials.empty()) return;
    for (const tinygltf::Material& m : model_.materials) materials_.names.push_back(m.name);
    materials_.gltf = &model_;
    materials_.source = path;
    polygon_material_.reserve(soup_.faces.size());
    for (const std::size_t d : soup_.face_drawn) {
      const int m = primitive(d).material;
      polygon_material_.push_back(
          m >= 0 && static_cast<std::size_t>(m) < model_.materials.size() ? m : -1);
    }
  }

  /// Each vertex's input normal in world space as a unit vector (zero: none), so that copies
  /// drawn by different nodes compare: a normal maps by the inverse transpose of its node's
  /// transform.
  void read_normals() {
    input_normal_.assign(vertex_count_, Eigen::Vector3d::Zero());
    for (std::size_t v = 0; v < vertex_count_; ++v) {
      const auto& s = soup_.sources[v];
      if (normals_[s.drawn].accessor < 0) continue;
      float f[3];
      std::memcpy(f, normals_[s.drawn].view.at(model_, s.element), sizeof f);
      const Eigen::Vector3d n =
          to_local_[s.drawn].topLeftCorner<3, 3>().transpose() * Eigen::Vector3d(f[0], f[1], f[2]);
      const double len = n.norm();
      if (len > 0.0 && std::isfinite(len)) input_normal_[v] = n / len;
    }
  }

  static void put_floats(tinygltf::Model& m, const gltf::ElementView& view, std::size_t element,
                         std::array<double, 3> value) {
    float f[3] = {static_cast<float>(value[0]), static_cast<float>(value[1]),
                  static_cast<float>(value[2])};
    std::memcpy(m.buffers[view.buffer].data.data() + view.offset + element * view.stride, f,
                sizeof f);
  }

  /// Area-weighted normals at the new positions, one per normal group (normal_groups.hpp): the
  /// copies at a position whose input normals are the same (seam copies, which the simulation
  /// moved together: no seam shows) share the sum over their triangles, while copies with their
  /// own normal (a flat side, a hard edge) get their own triangles' sum, so the edge stays hard.
  /// Then brought into each primitive's node space (the transpose of its world matrix: normals
  /// transform by the inverse transpose).
  void write_normals(tinygltf::Model& m, const Positions& x) const {
    bool any = false;
    for (const gltf::Written& n : normals_) any = any || n.accessor >= 0;
    if (!any) return;
    const std::vector<std::size_t> group =
        soup::normal_groups(soup::first_at_same_position(x), input_normal_);
    std::vector<Eigen::Vector3d> sum(group.size(), Eigen::Vector3d::Zero());
    for (const auto& f : soup_.faces) {
      const Eigen::Vector3d a = x.row(static_cast<Eigen::Index>(f[0])).transpose();
      const Eigen::Vector3d n = (x.row(static_cast<Eigen::Index>(f[1])).transpose() - a)
                                    .cross(x.row(static_cast<Eigen::Index>(f[2])).transpose() - a);
      for (const std::size_t v : f) sum[group[v]] += n;
    }
    for (std::size_t v = 0; v < vertex_count_; ++v) {
      const auto& s = soup_.sources[v];
      if (normals_[s.drawn].accessor < 0) continue;
      Eigen::Vector3d n = world_[s.drawn].topLeftCorner<3, 3>().transpose() * sum[group[v]];
      // A vertex whose faces have no area keeps the normal it had.
      if (!(n.norm() > 0.0) || !n.allFinite()) continue;
      n.normalize();
      put_floats(m, normals_[s.drawn].view, s.element, {n[0], n[1], n[2]});
    }
  }

  /// POSITION's min and max (the spec requires them) over all its elements, used or not.
  static void update_bounds(tinygltf::Model& m, const gltf::Written& w) {
    tinygltf::Accessor& a = m.accessors[static_cast<std::size_t>(w.accessor)];
    std::vector<double> lo(3, std::numeric_limits<double>::infinity()),
        hi(3, -std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < w.view.count; ++i) {
      float f[3];
      std::memcpy(f, w.view.at(m, i), sizeof f);
      for (std::size_t c = 0; c < 3; ++c)
        lo[c] = std::min(lo[c], static_cast<double>(f[c])),
        hi[c] = std::max(hi[c], static_cast<double>(f[c]));
    }
    if (w.view.count == 0) return;
    a.minValues = lo;
    a.maxValues = hi;
  }

  bool binary_;
  std::string path_;        ///< the input file: relative image URIs start from its folder
  std::string input_json_;  ///< what is written back, updated (gltf_json.hpp)
  tinygltf::Model model_;
  GltfSoup soup_;
  std::vector<Eigen::Matrix4d> world_,
      to_local_;  ///< per drawn primitive: node space to world and back
  std::vector<gltf::Written> positions_, normals_, texcoords_;  ///< per drawn primitive
  std::vector<Eigen::Vector3d> input_normal_;             ///< per vertex: read_normals
};

}  // namespace

std::unique_ptr<MeshDocument> parse_gltf_document(const std::string& name, const std::string& bytes,
                                                  bool binary) {
  return std::make_unique<GltfDocument>(name, bytes, binary);
}

std::optional<double> gltf_float32_spacing(const MeshDocument& doc, const Positions& x) {
  const auto* gltf = dynamic_cast<const GltfDocument*>(&doc);
  return gltf ? std::optional<double>(gltf->float32_spacing(x)) : std::nullopt;
}

std::optional<Positions> gltf_rounded(const MeshDocument& doc, const Positions& x) {
  const auto* gltf = dynamic_cast<const GltfDocument*>(&doc);
  return gltf ? std::optional<Positions>(gltf->rounded(x)) : std::nullopt;
}

}  // namespace shellcontract
