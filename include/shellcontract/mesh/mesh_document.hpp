// An input file kept whole, so that a run's result keeps what the simulation does not use (issue
// 56: texture coordinates, normals, groups, materials, polygons, extra PLY properties). The
// simulation sees the triangle mesh read_input_mesh builds; the document writes the same file
// with only the vertex positions (and, for OBJ, the normals) replaced. docs/design/attributes.md.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "shellcontract/core/types.hpp"
#include "shellcontract/mesh/surface_mesh.hpp"

namespace shellcontract {

/// The file's texture coordinates as the simulation mesh's faces use them (for the glTF's
/// TEXCOORD_0). A vertex may have several (a UV seam): the corners say which.
struct CornerTexcoords {
  std::vector<std::array<double, 2>> uv;  ///< the file's texture coordinates (u, v)
  /// Per simulation face (face index order), per corner in the order vertices_around_face lists
  /// them from the face's halfedge: an index into uv.
  std::vector<std::array<std::size_t, 3>> face_uv;
  bool empty() const { return uv.empty(); }
};

/// A mesh file kept as a document; the simulation's vertex i is the file's vertex i (the readers
/// never weld or reorder vertices). The faces are the file's polygons in file order.
class MeshDocument {
 public:
  virtual ~MeshDocument() = default;
  /// "obj" or "ply": the extension of the files this document writes.
  virtual std::string format() const = 0;
  /// The whole file with the vertex positions x (#V by 3, input units); everything else as read.
  /// @throws std::invalid_argument if x.rows() != vertex_count() or a coordinate is not finite
  virtual std::string text(const Positions& x) const = 0;

  std::size_t vertex_count() const { return vertex_count_; }
  std::size_t polygon_count() const {
    return polygon_start_.empty() ? 0 : polygon_start_.size() - 1;
  }
  /// Number of triangles read_input_mesh makes of the polygons (n corners: n - 2).
  std::size_t triangle_count() const;
  /// Whether this document stands for `mesh`, the mesh read_input_mesh made of the same file:
  /// same vertex count, same triangle count, and each triangle's corners among the vertices of
  /// the polygon it came from. False (the plain writer is then used) e.g. after `--repair`.
  bool matches(const Mesh& mesh) const;
  /// Texture coordinates by simulation face corner; empty when some corner of a polygon has none.
  /// @pre matches(mesh)
  CornerTexcoords texcoords(const Mesh& mesh) const;

 protected:
  /// The polygon each simulation face comes from: face i < #polygons is polygon i (its first
  /// triangle), further triangles of split polygons follow in polygon order (read_input_mesh).
  std::vector<std::size_t> face_origins() const;

  std::size_t vertex_count_ = 0;
  std::vector<std::size_t> polygon_start_;  ///< polygon p's corners are [start[p], start[p + 1])
  std::vector<std::size_t> corner_vertex_;  ///< 0-based vertex index of each corner
  std::vector<long long> corner_uv_;        ///< index into uv_ of each corner; -1 none
  std::vector<std::array<double, 2>> uv_;   ///< the file's texture coordinates
};

/// The document of an OBJ or PLY file (by extension); nullptr for OFF and STL, which hold
/// nothing besides positions and faces.
/// @throws InputError naming the file and line if it cannot be read as a document
std::unique_ptr<MeshDocument> read_mesh_document(const std::string& path);

/// An OBJ file's bytes as a document (src/mesh/obj_document.cpp): every line but `v` and `vn`
/// is written back verbatim; `v` lines get the new positions (anything after x y z, such as
/// vertex colours, kept); `vn` lines get the normals of the new positions.
/// @param name the file's name, for messages
/// @throws InputError "<name>: <problem>: line <n> ..." for a line it cannot read
std::unique_ptr<MeshDocument> parse_obj_document(const std::string& name, const std::string& bytes);

/// A PLY file's bytes as a document (src/mesh/ply_document.cpp): header and every element byte
/// for byte, but the vertices' x, y, z, written in their declared types and the file's format.
/// @throws InputError "<name>: <problem>: ..." for a file it cannot read
std::unique_ptr<MeshDocument> parse_ply_document(const std::string& name, const std::string& bytes);

/// Writes doc.text(x) to `path` atomically (write_text_atomic).
/// @throws UsageError if the file cannot be written
void write_mesh_document_atomic(const std::string& path, const MeshDocument& doc,
                                const Positions& x);

/// The shortest text that reads back to exactly v (std::to_chars); used by the documents.
std::string format_double(double v);

}  // namespace shellcontract
