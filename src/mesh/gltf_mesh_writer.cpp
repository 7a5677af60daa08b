// A bare triangle mesh as glTF 2.0 (see gltf_mesh_writer.hpp): the buffer is filled by the run's
// BufferBuilder and serialized by tinygltf, the two that write the run's .glb, so the repair
// output and the run's follow the same conventions (alignment, accessor bounds, index type).
#include "mesh/gltf_mesh_writer.hpp"

#include <tiny_gltf.h>

#include <climits>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include "export/gltf_buffer.hpp"
#include "mesh/seam_weld.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/export.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

/// Area-weighted normals (vertex_normals, as the run's .glb has them) in which the vertices at
/// one bitwise-identical position share the sum over all their triangles: copies that a file
/// split at a UV seam (kept as copies in a converted output) are one point of one surface, and
/// separate normals would show the seam as a crease.
Positions shared_position_normals(const Positions& x, const Faces& faces) {
  const std::vector<std::size_t> first = soup::first_at_same_position(x);
  Faces on_first = faces;
  for (Eigen::Index i = 0; i < on_first.size(); ++i)
    on_first.data()[i] = static_cast<int>(first[static_cast<std::size_t>(on_first.data()[i])]);
  const Positions n = vertex_normals(x, on_first);
  Positions out(x.rows(), 3);
  for (Eigen::Index v = 0; v < x.rows(); ++v)
    out.row(v) = n.row(static_cast<Eigen::Index>(first[static_cast<std::size_t>(v)]));
  return out;
}

/// The points as rows (they are checked finite by the callers that need it).
Positions as_rows(const std::vector<Point3>& points) {
  Positions x(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    x.row(static_cast<Eigen::Index>(i)) << points[i].x(), points[i].y(), points[i].z();
  return x;
}

/// Positions relative to `centre` as glTF stores them. The run's .glb does the same
/// (gltf_animation.cpp): float32 keeps about 7 digits of a coordinate, so a mesh far from the
/// origin stored absolute loses its shape, while relative to its own centre it keeps float
/// precision relative to its size.
gltf::Floats3 relative_floats(const Positions& x, const Vec3& centre) {
  return (x.rowwise() - centre.transpose()).cast<float>();
}

/// The largest coordinate change that storing `x` relative to `origin` makes (infinite where a
/// coordinate is beyond float32's range).
double storage_error(const Positions& x, const Vec3& origin) {
  const Positions placed = relative_floats(x, origin).cast<double>().rowwise() + origin.transpose();
  if (!placed.allFinite()) return std::numeric_limits<double>::infinity();
  return (placed - x).cwiseAbs().maxCoeff();
}

/// The node's translation: the bounding-box centre (gltf_centre), unless positions stored as they
/// are lose no more. Float32 input (a .glb, an STL) then comes back bit for bit, where digits taken
/// relative to a centre would round; a mesh far from the origin keeps its shape.
Vec3 storage_origin(const Positions& x) {
  const Vec3 centre = gltf_centre(x);
  if (x.rows() == 0 || centre == Vec3::Zero()) return centre;
  const double absolute = storage_error(x, Vec3::Zero());
  // Both infinite: the centre, and write_gltf_mesh_atomic refuses the mesh.
  return std::isfinite(absolute) && absolute <= storage_error(x, centre) ? Vec3::Zero() : centre;
}

}  // namespace

std::vector<Point3> points_as_stored_in_gltf(const std::vector<Point3>& points) {
  const Positions x = as_rows(points);
  const Vec3 centre = storage_origin(x);
  const Positions placed = relative_floats(x, centre).cast<double>().rowwise() + centre.transpose();
  std::vector<Point3> out;
  out.reserve(points.size());
  for (Eigen::Index i = 0; i < placed.rows(); ++i)
    out.emplace_back(placed(i, 0), placed(i, 1), placed(i, 2));
  return out;
}

void write_gltf_mesh_atomic(const std::string& path, const std::vector<Point3>& points,
                            const std::vector<std::vector<std::size_t>>& triangles, bool binary) {
  if (points.empty() || triangles.empty())
    throw std::invalid_argument("write_gltf_mesh_atomic: no vertices or no triangles");
  // Faces holds int indices, and glTF's largest index type is 32-bit unsigned.
  if (points.size() > static_cast<std::size_t>(INT_MAX))
    throw UsageError("cannot write '" + path + "': " + std::to_string(points.size()) +
                     " vertices are more than a glTF's 32-bit indices reach here");
  const Positions x = as_rows(points);
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    if (!x.row(i).allFinite())
      throw std::invalid_argument("write_gltf_mesh_atomic: vertex " + std::to_string(i) +
                                  " has a coordinate that is not finite");
  const Vec3 centre = storage_origin(x);
  const gltf::Floats3 stored = relative_floats(x, centre);
  if (!stored.allFinite())
    throw UsageError("cannot write '" + path +
                     "': the positions span more than glTF's 32-bit floats hold; write .off, "
                     ".obj or .ply");
  Faces faces(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    if (triangles[t].size() != 3)
      throw std::invalid_argument("write_gltf_mesh_atomic: polygon " + std::to_string(t) +
                                  " is not a triangle");
    for (std::size_t k = 0; k < 3; ++k) {
      if (triangles[t][k] >= points.size())
        throw std::invalid_argument("write_gltf_mesh_atomic: a triangle names a missing point");
      faces(static_cast<Eigen::Index>(t), static_cast<Eigen::Index>(k)) =
          static_cast<int>(triangles[t][k]);
    }
  }

  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "shellcontract repair";
  // Positions and normals (12 bytes each per vertex) and the indices (4 per corner).
  gltf::BufferBuilder bb(model, 24 * points.size() + 12 * triangles.size() + 8);
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.attributes["POSITION"] = bb.add_vec3(stored, true);
  prim.attributes["NORMAL"] = bb.add_vec3(shared_position_normals(x, faces).cast<float>(), false);
  prim.indices = bb.add_indices(faces);
  tinygltf::Mesh mesh;
  mesh.primitives.push_back(prim);
  model.meshes.push_back(mesh);
  gltf::add_single_node_scene(model, "", centre);
  model.buffers[0].data.resize((model.buffers[0].data.size() + 3) / 4 * 4, 0);

  write_file_atomic(path, [&](std::ostream& out) {
    tinygltf::TinyGLTF writer;
    // A .gltf is pretty-printed, as the run writes a .gltf result (gltf_document.cpp).
    if (!writer.WriteGltfSceneToStream(&model, out, !binary, binary) || !out)
      throw UsageError("cannot write '" + path + "': serializing the glTF failed");
  });
}

}  // namespace shellcontract
