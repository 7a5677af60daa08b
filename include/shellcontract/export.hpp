// Animated glTF 2.0 binary (.glb) of a run (docs/design/export.md): the mesh with one morph
// target per exported frame, played by a STEP animation of the morph weights.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "shellcontract/types.hpp"

namespace tinygltf {
class Model;
}

namespace shellcontract {

/// A per-vertex scalar field to show as colours (e.g. the fields of --fields).
struct NamedVertexField {
  std::string name;        ///< shown by the viewer, e.g. "mean_curvature"
  Eigen::VectorXd values;  ///< #V values, any units
};

/// An image file's bytes, held once however many materials carry them: copies of an ImageBytes
/// share one buffer, so a texture that many materials name is held once, not once per material.
class ImageBytes {
 public:
  ImageBytes() = default;
  /// Implicit, so that a material is written with its bytes: GltfMaterial{"m", c, bytes, mime}.
  ImageBytes(std::vector<unsigned char> bytes)  // NOLINT(google-explicit-constructor)
      : bytes_(bytes.empty()
                   ? nullptr
                   : std::make_shared<const std::vector<unsigned char>>(std::move(bytes))) {}
  bool empty() const { return bytes_ == nullptr; }
  std::size_t size() const { return bytes_ ? bytes_->size() : 0; }
  const unsigned char* data() const { return bytes_ ? bytes_->data() : nullptr; }
  /// The same buffer (a copy of one ImageBytes), not only equal bytes.
  bool shares(const ImageBytes& other) const { return bytes_ != nullptr && bytes_ == other.bytes_; }
  /// Equal bytes (the shared buffer compares at once).
  friend bool operator==(const ImageBytes& a, const ImageBytes& b) {
    return a.bytes_ == b.bytes_ || (a.bytes_ && b.bytes_ && *a.bytes_ == *b.bytes_);
  }

 private:
  std::shared_ptr<const std::vector<unsigned char>> bytes_;
};

/// A glTF PBR material (metallic-roughness) for some or all of the faces, e.g. from an OBJ's .mtl.
struct GltfMaterial {
  std::string name;
  std::array<double, 4> base_colour{1.0, 1.0, 1.0, 1.0};  ///< baseColorFactor, RGBA in [0, 1]
  /// Optional base colour texture: the image file's bytes, embedded as they are in the .glb's
  /// buffer, and its mimeType ("image/png" or "image/jpeg"). Empty: no texture.
  ImageBytes image;
  std::string image_mime_type;
  /// A glTF input's material (an index into GltfAnimation::material_source's materials),
  /// written as the input has it; the fields above are then unused. -1: none.
  int source_material = -1;
};

/// Everything the .glb holds. Positions are in the input's units and orientation.
struct GltfAnimation {
  std::string name = "shell";      ///< the node's and the mesh's name (the CLI: the input's stem)
  Faces faces;                     ///< #F by 3, counter-clockwise seen from outside
  std::vector<int> frame_numbers;  ///< the run's frame number of each entry of `frames`, increasing
  std::vector<Positions> frames;   ///< #V by 3 each; frames[0] is the base mesh
  double seconds_per_frame = 1.0 / 24.0;  ///< playback time between two consecutive run frames
                                          ///< (keyframe k is at (frame_numbers[k] -
                                          ///< frame_numbers[0]) * seconds_per_frame)
  std::vector<NamedVertexField> colour_fields;  ///< optional; each a custom SCALAR attribute
  int colour_frame = -1;  ///< the run frame whose values colour_fields hold; -1 unknown
  /// Optional: per frame (parallel to `frames`), the values of a field on that frame (float,
  /// #V each), so that a viewer colours each frame with its own values. Field name -> values.
  std::vector<std::pair<std::string, std::vector<Eigen::VectorXf>>> frame_fields;
  /// Optional texture coordinates (the input's): uv holds (u, v) pairs, face_uv (#F by
  /// 3, like faces) the index into uv of each face corner. Empty: no TEXCOORD_0.
  Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> uv;
  Faces face_uv;
  /// Optional vertex colours (the input's, for COLOR_0): colour holds RGBA rows on glTF's scale
  /// (0 to 1), face_colour (#F by 3, like faces) the row of each face corner's colour. Empty: no
  /// COLOR_0. colour_channels: 3 writes RGB (the input has no alpha), 4 RGBA.
  Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> colour;
  Faces face_colour;
  int colour_channels = 4;
  /// Optional normal groups of the input's shading (#F by 3, like faces; MeshDocument::
  /// normal_groups): corners of one vertex in different groups meet at a hard edge and get a
  /// normal each; -1: a corner without one. Empty: every vertex smooth.
  Faces face_normal;
  /// Optional, with face_normal: per face (#F), the input polygon it is a triangle of, in
  /// [0, #F); the triangles of one polygon count as one face for a hard normal (its vector area,
  /// as an OBJ result's normal). Empty: each face is a polygon of its own.
  std::vector<int> face_polygon;
  /// Optional materials (an OBJ's usemtl materials, from its .mtl files). A texture needs
  /// texture coordinates (TEXCOORD_0).
  std::vector<GltfMaterial> materials;
  /// Per face (#F, like faces): an index into materials, or -1 for a face without material
  /// (glTF's default material). Empty: every face has materials[0], or none when there is none.
  std::vector<int> face_material;
  /// A glTF input's materials, textures, samplers and images (gltf_materials), each image's
  /// bytes in its `image`, copied into the .glb as they are; null for other inputs.
  std::shared_ptr<const tinygltf::Model> material_source;
  /// Optional: per face (#F, like faces), its region of the local contraction (0, 1, ..., in the
  /// regions' order: a --regions file's lines) or -1 for a face in none; written as the
  /// categorical attribute _REGION. Empty: no regions, no attribute.
  std::vector<int> face_region;
};

/// What write_gltf_animation wrote.
struct GltfStats {
  std::size_t bytes = 0;         ///< file size
  std::size_t buffer_bytes = 0;  ///< binary chunk (positions, normals, colours, indices, keys)
};

/// Writes `animation` as a glTF 2.0 binary file, atomically (temporary file, then rename).
///
/// Layout: one scene, one node, one mesh with triangle primitives (one per material, below)
/// whose POSITION and NORMAL (float32, area-weighted vertex normals, unit length) are
/// frames[0]; for every later frame k a morph target holding the float32 displacements
/// POSITION(k) - POSITION(0) and NORMAL(k) - NORMAL(0), positions relative to the node's
/// `translation`, gltf_centre(frames[0]) (JSON doubles; none when zero: a mesh far from the origin
/// keeps its shape); one animation whose `weights` channel (STEP interpolation) has one keyframe
/// per frame with target k - 1 at weight 1 and the others at 0 (all 0 at frame 0). Each colour
/// field's values are a float SCALAR custom attribute named after it
/// ("mean_curvature" -> _MEAN_CURVATURE; three.js: _mean_curvature), never a COLOR_n (glTF
/// multiplies COLOR_0 with the base colour, which would tint a textured mesh). The mesh's `extras`
/// hold `frame_numbers`, `targetNames` ("frame_<n>") and `colour_fields` (name, values_attribute,
/// low / high: the 2nd and 98th percentiles of its values, the range a viewer maps onto blue -
/// white - red, and `frame`, the run frame whose values they are, when colour_frame is set).
///
/// With face_region, the float SCALAR custom attribute _REGION holds each glTF vertex's region
/// id (whole numbers, -1 for none), and the mesh's extras `categorical_fields` list it (name
/// "region", values_attribute "_REGION", none -1 and `ids`, the ids its faces use, increasing):
/// categories, which a viewer colours one apart from another, with no low / high. A vertex
/// whose faces are in different regions (a region's rim, where its faces meet those of no
/// region or of another region) is split as at a texture seam, one copy per region, so that
/// each face's three corners hold its own region's id.
///
/// Each of `frame_fields` is one float SCALAR accessor per frame (not a primitive attribute: glTF
/// morph targets cannot carry it), listed in the mesh's extras `frame_fields` (name, accessors,
/// and low / high: the 2nd and 98th percentiles of all its frames' values, one colour scale).
///
/// With texture coordinates, TEXCOORD_0 holds each vertex's (u, 1 - v): glTF's origin is the
/// top-left corner, OBJ's and PLY's the bottom-left. A vertex with several texture coordinates (a
/// seam) is split: glTF vertex i < #V is vertex i with the first coordinates its corners use, the
/// copies follow; every attribute and every morph target is copied with it.
///
/// With vertex colours, COLOR_0 (float VEC3 or VEC4) holds each glTF vertex's colour (that of
/// its corners: a vertex whose corners have different colours, a welded seam's copies, is split
/// as at a texture seam); unlike the fields', these are the input's own, which its materials
/// may rely on.
///
/// With normal groups, a vertex whose corners are in more than one group (a hard edge: a
/// flat-shaded side's corners, an OBJ's per-face `vn`) is split as a seam is, one copy per group
/// (and texture coordinate), and each copy's NORMAL, in every frame, is the area-weighted normal
/// of its group's faces alone (of their polygons whole, with face_polygon), so the edge stays
/// hard as the mesh moves. Every other vertex has
/// the area-weighted normal of all its faces (vertex_normals), as without normal groups.
///
/// The node and the mesh are called `name`. Primitives: one per material its faces use (a face
/// of none, face_material -1, in one more without material), in the order of each one's first
/// face; each has its own indices (its faces, in their order in `faces`) and shares every
/// attribute accessor, every morph target's accessors and so the mesh's weights and animation
/// with the others (glTF wants the same number of targets on every primitive of a mesh). One
/// material for every face (or none): one primitive. The glTF's materials are those used, in the
/// order of their primitives: pbrMetallicRoughness with baseColorFactor = base_colour,
/// metallicFactor 0 (an OBJ's diffuse surfaces are not metal; glTF's default, 1, renders them
/// dark), alphaMode BLEND when the alpha is below 1; an image, when given, is one bufferView of
/// the .glb's buffer (the file stays self-contained) read by a texture with a linear, repeating
/// sampler on TEXCOORD_0; materials whose images are the same bytes share one image and texture.
/// @throws std::invalid_argument for inconsistent sizes (texture coordinates, colours and
///         face_material too), no frames, non-increasing frame numbers, a non-finite coordinate,
///         a position (relative to the centre), displacement, field value, texture coordinate or
///         colour that float32 cannot hold (not finite, or beyond its range; positions all below
///         the smallest normal float, a mesh stored as a point), a material
///         index out of range, a material image without texture coordinates or mime type, or a
///         region id below -1 or from 2^24 on (float32 holds whole numbers exactly below it)
/// @throws UsageError if the file cannot be written, or would exceed the 4 GiB - 1 bytes a .glb
///         can hold (its lengths are 32-bit numbers): its true size is checked before its first
///         byte, and nothing is written then
GltfStats write_gltf_animation(const std::string& path, const GltfAnimation& animation);

/// The same file, freeing each frame of `animation` once it is in the file's buffer, so that the
/// frames and the buffer are not both held whole (a large mesh's .glb is hundreds of MB); the
/// frames are left empty.
GltfStats write_gltf_animation(const std::string& path, GltfAnimation&& animation);

/// The translation of write_gltf_animation's node for a mesh whose first frame is `rest`: its
/// bounding box's centre, in double (zero for no rows).
Vec3 gltf_centre(const Positions& rest);

/// Area-weighted vertex normals (unit length; (0, 0, 1) for a vertex whose faces have no area).
/// @throws std::invalid_argument for a face index outside [0, x.rows())
Positions vertex_normals(const Positions& x, const Faces& faces);

}  // namespace shellcontract
