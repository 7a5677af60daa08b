#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "export/gltf_buffer.hpp"
#include "export/gltf_input_materials.hpp"
#include "export/gltf_primitives.hpp"
#include "export/gltf_size.hpp"
#include "export/gltf_vertices.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/export.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/version.hpp"
#include "sim/fields.hpp"

namespace shellcontract {

namespace {

using gltf::BufferBuilder;
using gltf::Floats2;
using gltf::Floats3;

/// Whether every value is one a float32 accessor holds (glTF allows no inf or NaN there): a
/// finite double beyond float's range would be written as inf.
template <class M>
bool fits_float(const M& m) {
  return m.allFinite() &&
         (m.size() == 0 ||
          m.cwiseAbs().maxCoeff() <= static_cast<double>(std::numeric_limits<float>::max()));
}

/// The shortest text that reads back as `v`.
std::string shortest(double v) {
  char buf[64];
  const auto end = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, end.ptr);
}

/// Region ids are written as float32 (glTF allows no 32-bit integer custom attribute, and a
/// 16-bit one would hold too few ids): whole numbers are exact below 2^24.
constexpr int REGION_ID_LIMIT = 1 << 24;

constexpr const char* FLOAT_MAX_TEXT = "the largest 32-bit float (3.40282347e+38)";

/// Refuses positions, relative to the node's translation `centre`, that float32 cannot hold:
/// one beyond its range would be written as inf (a file no reader takes), and a mesh whose
/// relative coordinates are all below the smallest normal float would be stored as a point.
/// `frame`: the run frame named in the message.
void require_float_positions(const Positions& x, const Vec3& centre, int frame) {
  double largest = 0.0;
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    for (int k = 0; k < 3; ++k) {
      const double r = x(i, k) - centre(k);
      if (!(std::abs(r) <= static_cast<double>(std::numeric_limits<float>::max())))
        throw std::invalid_argument(
            "a glTF stores positions as 32-bit floats, relative to the mesh's centre: vertex " +
            std::to_string(i) + "'s " + "xyz"[k] + " at frame " + std::to_string(frame) + " is " +
            shortest(r) + " from it, beyond " + FLOAT_MAX_TEXT);
      largest = std::max(largest, std::abs(r));
    }
  if (largest > 0.0 && largest < static_cast<double>(std::numeric_limits<float>::min()))
    throw std::invalid_argument(
        "a glTF stores positions as 32-bit floats, relative to the mesh's centre: the farthest "
        "coordinate at frame " +
        std::to_string(frame) + " is " + shortest(largest) +
        " from it, below the smallest normal 32-bit float (1.17549435e-38): stored, the mesh "
        "would be a point or keep a few bits; scale the input up");
}

/// Why a field's values (in the input's units: a curvature of a mesh scaled by s scales by 1/s
/// or 1/s^2) do not fit float32: for a message that tells the user what to do.
std::string field_beyond_float(const std::string& name, const std::string& where) {
  return "a glTF stores fields as 32-bit floats: field '" + name + "' " + where + ", beyond " +
         FLOAT_MAX_TEXT +
         " (curvatures are in the input's units: a very small mesh has very "
         "large ones); scale the input, or leave out --gltf";
}

void check_input(const GltfAnimation& a) {
  if (a.frames.empty()) throw std::invalid_argument("write_gltf_animation: no frames");
  if (a.frame_numbers.size() != a.frames.size())
    throw std::invalid_argument("write_gltf_animation: " + std::to_string(a.frame_numbers.size()) +
                                " frame numbers for " + std::to_string(a.frames.size()) +
                                " frames");
  const Eigen::Index nv = a.frames[0].rows();
  for (std::size_t k = 0; k < a.frames.size(); ++k) {
    if (a.frames[k].rows() != nv)
      throw std::invalid_argument("write_gltf_animation: frame " + std::to_string(k) + " has " +
                                  std::to_string(a.frames[k].rows()) + " vertices, frame 0 has " +
                                  std::to_string(nv));
    if (!a.frames[k].allFinite())
      throw std::invalid_argument("write_gltf_animation: frame " +
                                  std::to_string(a.frame_numbers[k]) +
                                  " has a non-finite coordinate");
    if (k > 0 && a.frame_numbers[k] <= a.frame_numbers[k - 1])
      throw std::invalid_argument("write_gltf_animation: frame numbers must increase");
  }
  const Vec3 centre = gltf_centre(a.frames[0]);
  for (std::size_t k = 0; k < a.frames.size(); ++k)
    require_float_positions(a.frames[k], centre, a.frame_numbers[k]);
  if (a.faces.rows() == 0) throw std::invalid_argument("write_gltf_animation: no faces");
  if (a.faces.minCoeff() < 0 || a.faces.maxCoeff() >= nv)
    throw std::invalid_argument("write_gltf_animation: a face index is out of range");
  for (const NamedVertexField& f : a.colour_fields)
    if (f.values.size() != nv)
      throw std::invalid_argument("write_gltf_animation: colour field '" + f.name + "' has " +
                                  std::to_string(f.values.size()) + " values for " +
                                  std::to_string(nv) + " vertices");
    else if (!f.values.allFinite())
      throw std::invalid_argument("write_gltf_animation: colour field '" + f.name +
                                  "' has a non-finite value");
    else if (!fits_float(f.values)) {
      Eigen::Index i = 0;
      const double v = f.values.cwiseAbs().maxCoeff(&i);
      throw std::invalid_argument(
          field_beyond_float(f.name, "reaches " + shortest(v) + " at vertex " + std::to_string(i)));
    }
  if (a.face_uv.rows() > 0 || a.uv.rows() > 0) {
    if (a.face_uv.rows() != a.faces.rows())
      throw std::invalid_argument("write_gltf_animation: " + std::to_string(a.face_uv.rows()) +
                                  " rows of texture coordinate indices for " +
                                  std::to_string(a.faces.rows()) + " faces");
    if (a.uv.rows() == 0 || a.face_uv.minCoeff() < 0 || a.face_uv.maxCoeff() >= a.uv.rows())
      throw std::invalid_argument("write_gltf_animation: a texture coordinate index is out of range");
    if (!fits_float(a.uv))
      throw std::invalid_argument(
          "write_gltf_animation: a texture coordinate is not finite or beyond float32's range");
  }
  if (a.face_colour.rows() > 0 || a.colour.rows() > 0) {
    if (a.face_colour.rows() != a.faces.rows())
      throw std::invalid_argument("write_gltf_animation: " + std::to_string(a.face_colour.rows()) +
                                  " rows of colour indices for " + std::to_string(a.faces.rows()) +
                                  " faces");
    if (a.colour.rows() == 0 || a.face_colour.minCoeff() < 0 ||
        a.face_colour.maxCoeff() >= a.colour.rows())
      throw std::invalid_argument("write_gltf_animation: a colour index is out of range");
    if (!fits_float(a.colour))
      throw std::invalid_argument(
          "write_gltf_animation: a colour is not finite or beyond float32's range");
    if (a.colour_channels != 3 && a.colour_channels != 4)
      throw std::invalid_argument("write_gltf_animation: colour_channels is not 3 or 4");
  }
  if (a.face_normal.rows() > 0) {
    if (a.face_normal.rows() != a.faces.rows())
      throw std::invalid_argument("write_gltf_animation: " + std::to_string(a.face_normal.rows()) +
                                  " rows of normal groups for " + std::to_string(a.faces.rows()) +
                                  " faces");
    if (a.face_normal.minCoeff() < -1)
      throw std::invalid_argument("write_gltf_animation: a normal group below -1");
  }
  if (!a.face_polygon.empty()) {
    if (a.face_polygon.size() != static_cast<std::size_t>(a.faces.rows()))
      throw std::invalid_argument("write_gltf_animation: " + std::to_string(a.face_polygon.size()) +
                                  " face polygons for " + std::to_string(a.faces.rows()) +
                                  " faces");
    for (const int p : a.face_polygon)
      if (p < 0 || p >= a.faces.rows())
        throw std::invalid_argument("write_gltf_animation: a face's polygon " + std::to_string(p) +
                                    " is out of range (" + std::to_string(a.faces.rows()) +
                                    " faces)");
  }
  for (const auto& [name, values] : a.frame_fields) {
    if (values.size() != a.frames.size())
      throw std::invalid_argument("write_gltf_animation: frame field '" + name + "' has " +
                                  std::to_string(values.size()) + " frames, the animation " +
                                  std::to_string(a.frames.size()));
    for (std::size_t k = 0; k < values.size(); ++k) {
      const Eigen::VectorXf& v = values[k];
      if (v.size() != nv)
        throw std::invalid_argument("write_gltf_animation: frame field '" + name +
                                    "' has a frame of the wrong size");
      // A float field's inf is a double value that float32 could not hold (a NaN is the
      // caller's), as the CLI's curvature of a very small mesh.
      for (Eigen::Index i = 0; i < v.size(); ++i)
        if (std::isinf(v(i)))
          throw std::invalid_argument(
              field_beyond_float(name, "is beyond it at vertex " + std::to_string(i) +
                                           " of frame " + std::to_string(a.frame_numbers[k])));
      if (!v.allFinite())
        throw std::invalid_argument("write_gltf_animation: frame field '" + name +
                                    "' has a NaN at frame " + std::to_string(a.frame_numbers[k]));
    }
  }
  if (!a.face_region.empty()) {
    if (a.face_region.size() != static_cast<std::size_t>(a.faces.rows()))
      throw std::invalid_argument("write_gltf_animation: " + std::to_string(a.face_region.size()) +
                                  " face regions for " + std::to_string(a.faces.rows()) + " faces");
    for (std::size_t f = 0; f < a.face_region.size(); ++f)
      if (a.face_region[f] < -1 || a.face_region[f] >= REGION_ID_LIMIT)
        throw std::invalid_argument(
            "write_gltf_animation: face " + std::to_string(f) + " has region id " +
            std::to_string(a.face_region[f]) + " (ids are -1 for none, or 0 to " +
            std::to_string(REGION_ID_LIMIT - 1) + ", which a 32-bit float holds exactly)");
  }
  if (!(a.seconds_per_frame > 0.0))
    throw std::invalid_argument("write_gltf_animation: seconds_per_frame <= 0");
  gltf::check_materials(a);
}

tinygltf::Value string_array(const std::vector<std::string>& s) {
  tinygltf::Value::Array a;
  for (const std::string& x : s) a.emplace_back(x);
  return tinygltf::Value(a);
}

}  // namespace

Vec3 gltf_centre(const Positions& rest) {
  if (rest.rows() == 0) return Vec3::Zero();
  // Halves summed: the sum of two coordinates near the double range's end would overflow.
  return (0.5 * rest.colwise().minCoeff() + 0.5 * rest.colwise().maxCoeff()).transpose();
}

Positions vertex_normals(const Positions& x, const Faces& faces) {
  // A library caller's faces are checked as write_gltf_animation checks them: an index out of
  // range had read and written past the arrays (a crash, or silently wrong normals).
  if (faces.size() > 0 && (faces.minCoeff() < 0 || faces.maxCoeff() >= x.rows()))
    throw std::invalid_argument("vertex_normals: a face index is out of range (" +
                                std::to_string(x.rows()) + " vertices)");
  Positions n = Positions::Zero(x.rows(), 3);
  for (Eigen::Index j = 0; j < faces.rows(); ++j) {
    const Vec3 a = x.row(faces(j, 0)), b = x.row(faces(j, 1)), c = x.row(faces(j, 2));
    const Vec3 w = (b - a).cross(c - a);  // twice the area times the unit normal
    for (int k = 0; k < 3; ++k) n.row(faces(j, k)) += w.transpose();
  }
  for (Eigen::Index i = 0; i < n.rows(); ++i) {
    const double len = n.row(i).norm();
    if (len > 0.0 && std::isfinite(len))
      n.row(i) /= len;
    else
      n.row(i) << 0.0, 0.0, 1.0;
  }
  return n;
}

namespace {

/// Rows of `a` for the glTF's vertices (a itself when nothing was split).
template <class M>
M gather(M a, const std::vector<Eigen::Index>& source) {
  if (static_cast<std::size_t>(a.rows()) == source.size()) return a;
  M out(static_cast<Eigen::Index>(source.size()), a.cols());
  for (std::size_t i = 0; i < source.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = a.row(source[i]);
  return out;
}

/// A custom attribute's name for a field: "_" and the name in capitals, other characters than
/// letters and digits as "_" (glTF: application-specific semantics start with "_").
std::string custom_attribute(const std::string& name) {
  std::string s = "_";
  for (const char c : name)
    s += std::isalnum(static_cast<unsigned char>(c)) ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : '_';
  return s;
}

/// write_gltf_animation; with `consumed` (a.frames itself), each frame after frame 0 is freed
/// once its morph target is in the buffer.
GltfStats write_gltf(const std::string& path, const GltfAnimation& a,
                     std::vector<Positions>* consumed) {
  check_input(a);
  const gltf::VertexSplit split = gltf::split_vertices(a);
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = std::string("shellcontract ") + build_version();  // which build wrote it
  BufferBuilder bb(model, gltf::buffer_capacity(a, split.source.size(), a.frames.size()));

  // The primitives' indices first (a single primitive's file is laid out as before materials
  // made several); everything else is one set, shared by every primitive.
  const std::vector<gltf::PrimitiveFaces> parts = gltf::faces_by_material(a, split.faces);
  std::vector<int> indices;
  for (const gltf::PrimitiveFaces& p : parts) indices.push_back(bb.add_indices(p.faces));
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  // Positions relative to the rest bounding box's centre, which is the node's translation (JSON
  // doubles): float32 keeps about 7 digits of a coordinate, so a mesh far from the origin (a
  // statue in UTM metres, northing 5e6: float spacing 0.5) stored absolute lost its shape;
  // relative, it keeps float precision relative to its own size.
  const Vec3 centre = gltf_centre(a.frames[0]);
  const Floats3 x0 = (a.frames[0].rowwise() - centre.transpose()).cast<float>();
  const Positions x0_stored = x0.cast<double>();  // what a reader gets for frame 0
  // Normals on the simulation's mesh, so that a seam's copies share theirs (no visible seam);
  // a hard edge's copies each have their own faces' (gltf_vertices.hpp).
  const Positions n0 = gltf::split_normals(split, a.frames[0], a.faces);
  prim.attributes["POSITION"] = bb.add_vec3(gather(x0, split.source), true);
  prim.attributes["NORMAL"] = bb.add_vec3(n0.cast<float>(), false);
  if (!split.uv.empty()) {
    Floats2 texcoords(static_cast<Eigen::Index>(split.uv.size()), 2);
    for (std::size_t i = 0; i < split.uv.size(); ++i) {
      const Eigen::Index t = split.uv[i] < 0 ? 0 : split.uv[i];  // < 0: a vertex no face uses
      texcoords(static_cast<Eigen::Index>(i), 0) = static_cast<float>(a.uv(t, 0));
      texcoords(static_cast<Eigen::Index>(i), 1) = static_cast<float>(1.0 - a.uv(t, 1));
    }
    prim.attributes["TEXCOORD_0"] = bb.add_vec2(texcoords);  // (u, 1 - v)
  }
  if (!split.colour.empty()) {
    // The input's colours, as they are: unlike the fields' (below), its materials may rely on
    // them (glTF multiplies the base colour by COLOR_0).
    const auto n = static_cast<Eigen::Index>(split.colour.size());
    Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rgba(n,
                                                                               a.colour_channels);
    for (Eigen::Index i = 0; i < n; ++i) {
      const int c = split.colour[static_cast<std::size_t>(i)];
      for (int k = 0; k < a.colour_channels; ++k)
        rgba(i, k) =
            c < 0 ? 1.0f : static_cast<float>(a.colour(c, k));  // < 0: a vertex no face uses
    }
    prim.attributes["COLOR_0"] = bb.add_colours(rgba);
  }

  tinygltf::Value::Object extras;
  // The regions first, so that a colour field called "region" is the one renamed (below).
  tinygltf::Value::Array categorical_info;
  if (!split.region.empty()) {
    Eigen::VectorXf ids(static_cast<Eigen::Index>(split.region.size()));
    for (std::size_t i = 0; i < split.region.size(); ++i)
      ids(static_cast<Eigen::Index>(i)) = static_cast<float>(split.region[i]);
    prim.attributes["_REGION"] = bb.add_vertex_scalars(ids);
    std::vector<int> used;
    for (const int r : a.face_region)
      if (r >= 0) used.push_back(r);
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    tinygltf::Value::Array id_list;
    for (const int r : used) id_list.emplace_back(r);
    tinygltf::Value::Object info;
    info["name"] = tinygltf::Value(std::string("region"));
    info["values_attribute"] = tinygltf::Value(std::string("_REGION"));
    info["none"] = tinygltf::Value(-1);
    // tinygltf writes an empty array as null: a run whose regions have no face lists none.
    if (!id_list.empty()) info["ids"] = tinygltf::Value(id_list);
    categorical_info.emplace_back(info);
  }
  tinygltf::Value::Array colour_info;
  for (std::size_t i = 0; i < a.colour_fields.size(); ++i) {
    // Only the values, as a custom attribute: glTF's COLOR_0 multiplies the base colour, so a
    // field's colours there would tint every textured asset in Blender and three.js. A viewer
    // maps the values to colours over the range given in the extras.
    const Eigen::VectorXd& v = a.colour_fields[i].values;
    const std::vector<double> all(v.data(), v.data() + v.size());
    std::string values = custom_attribute(a.colour_fields[i].name);
    // Two names that map to the same attribute: the field's index appended.
    if (prim.attributes.count(values)) values += "_" + std::to_string(i);
    prim.attributes[values] =
        bb.add_vertex_scalars(gather<Eigen::VectorXf>(v.cast<float>(), split.source));
    tinygltf::Value::Object info;
    info["name"] = tinygltf::Value(a.colour_fields[i].name);
    info["values_attribute"] = tinygltf::Value(values);
    if (a.colour_frame >= 0) info["frame"] = tinygltf::Value(a.colour_frame);
    info["low"] = tinygltf::Value(field_percentile(all, 0.02));
    info["high"] = tinygltf::Value(field_percentile(all, 0.98));
    colour_info.emplace_back(info);
  }

  // Per-frame field values: one accessor per frame, one colour scale over all of them.
  tinygltf::Value::Array frame_field_info;
  for (const auto& [name, values] : a.frame_fields) {
    std::vector<float> all;
    all.reserve(values.size() * static_cast<std::size_t>(values[0].size()));
    tinygltf::Value::Array accessors;
    for (const Eigen::VectorXf& v : values) {
      all.insert(all.end(), v.data(), v.data() + v.size());
      accessors.emplace_back(bb.add_vertex_scalars(gather(v, split.source)));
    }
    std::sort(all.begin(), all.end());
    // Nearest rank, as field_percentile (the fields PLY and the colour fields above).
    auto at = [&](double q) { return static_cast<double>(all[static_cast<std::size_t>(std::lround(q * static_cast<double>(all.size() - 1)))]); };
    tinygltf::Value::Object info;
    info["name"] = tinygltf::Value(name);
    info["accessors"] = tinygltf::Value(accessors);
    info["low"] = tinygltf::Value(at(0.02));
    info["high"] = tinygltf::Value(at(0.98));
    frame_field_info.emplace_back(info);
  }

  // Morph targets: displacements from what the reader has for frame 0, so that base plus
  // displacement rounds once (float) away from each frame.
  std::vector<std::string> target_names;
  for (std::size_t k = 1; k < a.frames.size(); ++k) {
    const Positions d = (a.frames[k].rowwise() - centre.transpose()) - x0_stored;
    if (!fits_float(d))  // relative positions fit (checked); their difference may not
      throw std::invalid_argument(
          "a glTF stores positions as 32-bit floats: frame " + std::to_string(a.frame_numbers[k]) +
          "'s displacement from frame " + std::to_string(a.frame_numbers[0]) + " is beyond " +
          FLOAT_MAX_TEXT);
    const Floats3 dx = gather<Floats3>(d.cast<float>(), split.source);
    const Floats3 dn = (gltf::split_normals(split, a.frames[k], a.faces) - n0).cast<float>();
    if (consumed) Positions().swap((*consumed)[k]);
    std::map<std::string, int> target;
    target["POSITION"] = bb.add_vec3(dx, true);
    target["NORMAL"] = bb.add_vec3(dn, false);
    prim.targets.push_back(target);
    target_names.push_back("frame_" + std::to_string(a.frame_numbers[k]));
  }

  std::vector<int> materials;
  if (a.material_source) {
    // A glTF input's materials, carried whole: their indices stay the input's.
    gltf::add_source_materials(model, bb, *a.material_source);
    for (const gltf::PrimitiveFaces& p : parts)
      materials.push_back(
          p.material < 0 ? -1 : a.materials[static_cast<std::size_t>(p.material)].source_material);
  } else {
    materials = gltf::add_materials(model, bb, a.materials, parts);
  }

  tinygltf::Mesh mesh;
  mesh.name = a.name;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    prim.indices = indices[p];
    prim.material = materials[p];
    mesh.primitives.push_back(prim);
  }
  mesh.weights.assign(prim.targets.size(), 0.0);
  tinygltf::Value::Array frame_numbers;
  for (int f : a.frame_numbers) frame_numbers.emplace_back(f);
  extras["frame_numbers"] = tinygltf::Value(frame_numbers);
  // tinygltf writes an empty array as null: a list with nothing in it is left out.
  if (!target_names.empty()) extras["targetNames"] = string_array(target_names);
  if (!colour_info.empty()) extras["colour_fields"] = tinygltf::Value(colour_info);
  if (!categorical_info.empty()) extras["categorical_fields"] = tinygltf::Value(categorical_info);
  if (!frame_field_info.empty()) extras["frame_fields"] = tinygltf::Value(frame_field_info);
  extras["seconds_per_frame"] = tinygltf::Value(a.seconds_per_frame);
  mesh.extras = tinygltf::Value(extras);
  model.meshes.push_back(mesh);

  gltf::add_single_node_scene(model, a.name, centre);

  if (!prim.targets.empty()) {
    // One keyframe per frame: frame 0 has every weight at 0, frame k has target k - 1 at 1.
    const std::size_t nk = a.frames.size(), nt = prim.targets.size();
    std::vector<float> times(nk), weights(nk * nt, 0.0f);
    for (std::size_t k = 0; k < nk; ++k) {
      times[k] =
          static_cast<float>((a.frame_numbers[k] - a.frame_numbers[0]) * a.seconds_per_frame);
      if (k > 0) weights[k * nt + (k - 1)] = 1.0f;
    }
    tinygltf::AnimationSampler sampler;
    sampler.input = bb.add_scalars(times, true);
    sampler.output = bb.add_scalars(weights, false);
    sampler.interpolation = "STEP";
    tinygltf::AnimationChannel channel;
    channel.sampler = 0;
    channel.target_node = 0;
    channel.target_path = "weights";
    tinygltf::Animation anim;
    anim.name = "contraction";
    anim.samplers.push_back(sampler);
    anim.channels.push_back(channel);
    model.animations.push_back(anim);
  }

  model.buffers[0].data.resize((model.buffers[0].data.size() + 3) / 4 * 4, 0);
  GltfStats stats;
  stats.buffer_bytes = model.buffers[0].data.size();
  // Straight into the file: through a string first, a large mesh's .glb was held three more
  // times in memory (lab/history.md).
  // Its true size checked first (write_glb): a .glb over 4 GiB is refused, never written with
  // wrapped lengths.
  write_file_atomic(path,
                    [&](std::ostream& out) { stats.bytes = gltf::write_glb(path, model, out); });
  return stats;
}

}  // namespace

GltfStats write_gltf_animation(const std::string& path, const GltfAnimation& animation) {
  return write_gltf(path, animation, nullptr);
}

GltfStats write_gltf_animation(const std::string& path, GltfAnimation&& animation) {
  return write_gltf(path, animation, &animation.frames);
}

}  // namespace shellcontract
