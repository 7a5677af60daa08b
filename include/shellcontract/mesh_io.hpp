// Reading, checking and writing meshes (docs/architecture.md, "From a file to a contracted mesh"):
// read_input_mesh and its checks, meshes from plain arrays (Python, C++ callers), OBJ and PLY
// documents that keep their attributes, and the atomic writers every output goes through.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "shellcontract/mesh.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

/// What the input check found and did. Warnings are for the user (printed on stderr by the CLI).
struct InputReport {
  std::size_t vertices = 0;
  std::size_t faces = 0;            ///< after triangulation
  std::size_t triangulated_faces = 0;  ///< input polygons with more than 3 vertices that were split
  std::vector<std::size_t> zero_area_faces;  ///< face indices (output order) with ~zero area
  bool reoriented = false;          ///< the mesh was inside-out and its faces were flipped
  std::size_t components = 0;       ///< connected components
  double volume = 0.0;              ///< enclosed volume after reorientation (input units; inf beyond ~1e102 per coordinate)
  std::vector<std::string> warnings;
  /// Input vertices welded into another at the same position (a mesh split along its UV seams:
  /// docs/design/attributes.md, "Seams"); 0 for a mesh that is closed as given.
  std::size_t welded_vertices = 0;
  /// What the check did that is worth saying but is no problem (the CLI prints "note: ...").
  std::vector<std::string> notes;
  double read_seconds = 0.0;   ///< read_input_mesh: reading the file into a polygon soup
  double check_seconds = 0.0;  ///< read_input_mesh: checking it and building the mesh
};

/// Reads OFF/OBJ/PLY/STL (by extension; read_polygon_soup) and checks that the mesh is a
/// closed, manifold triangle mesh with finite coordinates, a nonzero finite bounding-box diagonal
/// and a positive enclosed volume (measured as the simulator measures it): the one decision of
/// what `check`, `run` and `regions` can use. Polygons are triangulated (with a warning); an
/// inside-out mesh is reoriented (with a warning); zero-area faces are reported. A mesh that is
/// open as given, but closed once its vertices at bitwise-identical positions are welded (split
/// UV seams), is returned welded, with a note (see "Seams" below). Geometric tests
/// run on coordinates normalized to a unit bounding-box diagonal, so any scale from 1e-150 to
/// 1e150 gives the same answers.
/// @throws InputError naming the file and the problem (and the face, vertex or line where known),
///         for any file whatever its bytes (also when memory runs out while reading it)
Mesh read_input_mesh(const std::string& path, InputReport* report = nullptr);

/// read_input_mesh's checks on a polygon soup already in memory (points in input units): the
/// same decision, for a mesh built by the program (repair_input_mesh). Messages start with `name`.
/// @throws InputError as read_input_mesh
Mesh check_input_soup(const std::string& name, std::vector<Point3> points,
                      const std::vector<std::vector<std::size_t>>& polygons, InputReport* report = nullptr);

/// Writes the mesh connectivity with the vertex positions x (row i = vertex i, input units),
/// keeping vertex and face order and each face's first corner, with CGAL's writer for the
/// extension (OFF, OBJ, STL; PLY through write_ply_atomic) at 17 significant digits, so
/// that the doubles read back bitwise. Written to a temporary file in the same folder, then
/// renamed, so a failure never leaves a partial file. A welded mesh is written with its input's
/// vertices and faces (mesh_for_output). The library's first write (this, write_ply_atomic,
/// write_text_atomic, write_file_atomic, check_output_files) installs a handler for SIGINT,
/// SIGTERM, SIGHUP and SIGUSR1, each only where its action is still the default, that removes
/// the process's own temporaries and then ends the process by the same signal; a host that
/// handles them installs its handlers first, or opts out (shellcontract/signals.hpp).
/// Numbers are written in the classic "C" form whatever the global C++ locale.
/// @param x one row per mesh vertex, or (a welded mesh) one per input vertex
/// @param binary a binary PLY (little-endian doubles: still bitwise) or STL (32-bit floats: the
///        positions rounded to float); OFF and OBJ are text whatever it says
/// @throws UsageError if the file cannot be written or the extension is unknown, or for an STL
///         in which two vertices would be stored at one position (an STL keeps no vertex
///         identity: read back they would be one vertex, another mesh; copies of a welded
///         vertex may share one)
/// @throws std::invalid_argument if x has another number of rows, a coordinate that is not
///         finite, or the mesh has garbage
void write_mesh_atomic(const std::string& path, const Mesh& mesh, const Positions& x, bool binary = false);

/// The mesh to give write_ply_atomic: a copy of `mesh` (vertex and face order and each face's
/// first corner kept) with its points set to x and no property maps, to which the caller
/// attaches the properties to write. For a welded mesh, the input's vertices and faces instead
/// (input_faces, input_positions): vertex i of the copy is input vertex i, whose data is that of
/// mesh vertex input_vertex_map(mesh)[i].
/// @param x #V by 3 positions, row i = vertex i; or (a welded mesh) one row per input vertex
/// @throws std::invalid_argument if x has another number of rows or the mesh has garbage
Mesh mesh_for_output(const Mesh& mesh, const Positions& x);

/// The one PLY writer (plain meshes, regions, fields): CGAL's Surface_mesh PLY writer, ASCII with 17
/// significant digits (or binary little-endian), atomically (temporary file + rename). Every vertex and face property map
/// of `mesh` with a simple type (int8..int64, float, double) is written as a property of its
/// element, named without the "v:"/"f:" prefix, in the order the maps were attached;
/// "v:color" / "f:color" (CGAL::IO::Color) become red, green, blue, alpha (uchar). Vertex
/// properties follow x, y, z; face properties follow vertex_indices.
/// @param mesh     usually built by mesh_for_output, so that only the maps meant for the file are on it
/// @param comments written as "comment" lines of the header, one per line of the string
/// @throws UsageError if the file cannot be written
void write_ply_atomic(const std::string& path, const Mesh& mesh, const std::string& comments = "",
                      bool binary = false);

/// Writes text to path atomically (temporary file + rename; links and descriptors as
/// write_file_atomic). @throws UsageError on failure
void write_text_atomic(const std::string& path, const std::string& text);

/// Writes a file atomically through `write`, which writes straight into a temporary file next to
/// `path` (no copy in memory: for large binary files written in a few large pieces, the .glb);
/// then renames it over `path`. If `write` throws, no file is left and the exception passes.
/// A symbolic link is followed: its target is replaced (the temporary beside the target) and the
/// link kept. A path naming a descriptor of this process (/dev/stdout, /dev/stderr, /dev/fd/N,
/// /proc/self/fd/N, or a link to one) is written straight into that descriptor, never replaced;
/// what `write` writes is then held in memory and written once it returns
/// (docs/design/output-safety.md, "Symbolic links and streams"). A replaced file keeps its
/// mode, and its owner and group where the caller may set them (root).
/// @throws UsageError if the file cannot be created or written
void write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& write);

// Seams (docs/design/attributes.md): read_input_mesh and mesh_from_arrays weld an input that is
// open only because its vertices are split at UV seams (copies at bitwise-identical positions).
// The simulation runs on the welded mesh; its f:input_corners property map keeps each face's
// corners as the input numbered them, from which every output gives the input's vertices back,
// each copy at its welded vertex's position. For any other mesh these are the identity.

/// Whether the mesh is a welded input's (it carries the input's corners).
bool has_welded_seams(const Mesh& mesh);

/// The input's vertex count: mesh.number_of_vertices() plus the welded copies.
std::size_t input_vertex_count(const Mesh& mesh);

/// Per input vertex, the mesh vertex it was welded into (the identity for a mesh not welded).
std::vector<std::size_t> input_vertex_map(const Mesh& mesh);

/// Per face (face order), its corners as the input numbered them, in the order
/// vertices_around_face lists the face's corners from its halfedge (the mesh's own corner
/// vertices for a mesh not welded).
std::vector<std::array<std::size_t, 3>> input_faces(const Mesh& mesh);

/// Positions of the input's vertices: x (one row per mesh vertex) with each copy given its
/// welded vertex's row. x as it is when it already has one row per input vertex (or the mesh
/// was not welded).
/// @throws std::invalid_argument if x has neither the mesh's nor the input's vertex count
Positions input_positions(const Mesh& mesh, const Positions& x);

}  // namespace shellcontract

// A checked Mesh from in-memory arrays (the Python module's numpy input, a C++ caller's buffers),
// with the checks and messages of read_input_mesh (shellcontract/mesh_io.hpp) for a triangle soup.
namespace shellcontract {

/// A read-only view of a triangle soup held by the caller; nothing is copied until the Mesh is
/// built. Rows are C-contiguous: vertex i is vertices[3i .. 3i+2], face j is faces[3j .. 3j+2].
/// Exactly one of faces32 / faces64 is set.
struct TriangleSoupView {
  const double* vertices = nullptr;  ///< #V by 3, any length unit
  std::size_t num_vertices = 0;
  const std::int32_t* faces32 = nullptr;  ///< #F by 3 vertex indices, 0-based
  const std::int64_t* faces64 = nullptr;  ///< #F by 3 vertex indices, 0-based
  std::size_t num_faces = 0;
};

/// Builds the mesh of a triangle soup after the checks read_input_mesh applies to a file: finite
/// coordinates, indices in range, no repeated corner, no duplicate face, no isolated vertex, every
/// edge shared by exactly two faces in opposite directions (closed, manifold, consistently
/// oriented), one fan per vertex. Zero-area faces are reported. Vertex and face order are kept,
/// and each face lists its corners as given. Arrays that are open only along split seams are
/// welded as read_input_mesh welds a file ("Seams" above).
/// @param name     what the messages call the input (read_input_mesh uses the file name)
/// @param reorient flip inside-out components as read_input_mesh does (with a warning); false
///                 keeps the faces exactly as given (writing a result back)
/// @throws InputError "<name>: <problem>: <where and details>", as read_input_mesh (an empty
///         soup: "empty mesh")
/// @throws std::invalid_argument for a view that is not one: none or both of faces32 and
///         faces64 set, or no vertices array for its vertex count
Mesh mesh_from_arrays(const TriangleSoupView& soup, const std::string& name,
                      InputReport* report = nullptr, bool reorient = true);

}  // namespace shellcontract

namespace tinygltf {
class Model;
}

// An input file kept whole, so that a run's result keeps what the simulation does not use (issue
// 56: texture coordinates, normals, groups, materials, polygons, extra PLY properties). The
// simulation sees the triangle mesh read_input_mesh builds; the document writes the same file
// with only the vertex positions (and, for OBJ, the normals) replaced. docs/design/attributes.md.
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

/// The file's vertex colours as the simulation mesh's faces use them (for the glTF's COLOR_0):
/// an OBJ's `v x y z r g b`, a PLY's red, green, blue (and alpha), a glTF's COLOR_0.
struct CornerColours {
  /// Per file vertex: red, green, blue, alpha on glTF's scale, 0 to 1 (a PLY's integer colours
  /// divided by their type's largest value, floats and an OBJ's numbers as written; alpha 1
  /// where the file has none).
  std::vector<std::array<double, 4>> rgba;
  int channels = 0;  ///< 3 (the file has no alpha) or 4
  /// Per simulation face (face index order), per corner in CornerTexcoords' order: an index into
  /// rgba (the corner's file vertex).
  std::vector<std::array<std::size_t, 3>> face_colour;
  bool empty() const { return rgba.empty(); }
};

/// Which corners of the simulation mesh's faces share a normal in the file (for the glTF's
/// NORMAL): a flat-shaded side or a hard edge is a vertex whose corners have different groups.
struct CornerNormalGroups {
  /// Per simulation face (face index order), per corner in CornerTexcoords' order: its normal
  /// group. Corners of one simulation vertex with the same group are smoothed together; -1: the
  /// file gives the corner no normal. The numbers mean nothing beyond equality at one vertex (an
  /// OBJ's corners with the same `vn` value; a PLY's or glTF's copies at one position with the
  /// same normal).
  std::vector<std::array<long long, 3>> face_group;
  /// Per simulation face, the file's polygon it is (a part of): the triangles of a polygon count
  /// as one face for its corners' normals (its vector area), as they do in an OBJ's result.
  std::vector<std::size_t> face_polygon;
  bool empty() const { return face_group.empty(); }
};

/// The materials an OBJ's faces use (`usemtl`) and the libraries that define them (`mtllib`),
/// or the texture files a PLY's header names (`comment TextureFile`), for the glTF's material.
struct FaceMaterials {
  std::vector<std::string> names;  ///< the material names, in order of first use
  /// Per simulation face (face index order): an index into names; -1 for a face after no usemtl.
  std::vector<int> face_material;
  struct Library {
    std::string path;      ///< the .mtl file as the process finds it (from the OBJ's folder)
    std::size_t line = 0;  ///< the OBJ's mtllib line that names it
    bool found = false;    ///< the file exists
  };
  std::vector<Library> libraries;
  /// A material that is nothing but a texture file the mesh file names itself (a PLY's
  /// `comment TextureFile <path>` line), with no library: parallel to names; empty for an OBJ.
  struct Texture {
    std::string path;      ///< the image as found from the PLY's folder; empty: none named
    std::size_t line = 0;  ///< the header line that names it
  };
  std::vector<Texture> textures;
  /// A glTF input's own materials: its parsed model (materials, textures, samplers, images and
  /// the buffers of embedded images), owned by the document, which must outlive this; names are
  /// its materials' names, index for index. Null for an OBJ or a PLY.
  const tinygltf::Model* gltf = nullptr;
  std::string source;  ///< the OBJ, PLY or glTF file, for messages and its folder
  bool empty() const { return names.empty(); }
};

/// A mesh file kept as a document; the simulation's vertex i is the file's vertex i (the readers
/// never reorder vertices; a mesh they welded along its seams names the file's vertices in
/// input_faces). The faces are the file's polygons in file order.
class MeshDocument {
 public:
  virtual ~MeshDocument() = default;
  /// "obj", "ply", "glb" or "gltf": the extension of the files this document writes.
  virtual std::string format() const = 0;
  /// The whole file with the vertex positions x (#V by 3, input units); everything else as read.
  /// A welded mesh's positions are given as input_positions(mesh, x).
  /// @throws std::invalid_argument if x.rows() != vertex_count() or a coordinate is not finite
  virtual std::string text(const Positions& x) const = 0;
  /// text(x) for a file written to `output_path`: an OBJ's mtllib paths, relative to the file's
  /// folder, are rewritten to name the same .mtl files from the output's folder when it is
  /// another (docs/design/attributes.md, "Material libraries"); a library that does not exist is
  /// written as read, with a warning naming the input file and line appended to `warnings`.
  /// Everything else as text(x).
  virtual std::string text_for(const std::string& output_path, const Positions& x,
                               std::vector<std::string>* warnings) const {
    (void)output_path;
    (void)warnings;
    return text(x);
  }

  std::size_t vertex_count() const { return vertex_count_; }
  std::size_t polygon_count() const {
    return polygon_start_.empty() ? 0 : polygon_start_.size() - 1;
  }
  /// Number of triangles read_input_mesh makes of the polygons (n corners: n - 2).
  std::size_t triangle_count() const;
  /// Whether this document stands for `mesh`, the mesh read_input_mesh made of the same file:
  /// same (input) vertex count, same triangle count, and each triangle's (input) corners among
  /// the vertices of the polygon it came from. False (the plain writer is then used) e.g. after `--repair`.
  bool matches(const Mesh& mesh) const;
  /// Texture coordinates by simulation face corner; empty when some corner of a polygon has none.
  /// @pre matches(mesh)
  CornerTexcoords texcoords(const Mesh& mesh) const;
  /// Vertex colours by simulation face corner; empty when the file has none (or not every vertex
  /// has one).
  /// @pre matches(mesh)
  CornerColours colours(const Mesh& mesh) const;
  /// Refuses what a glTF cannot hold of the texture coordinates its corners use (texcoords) and
  /// of its vertex colours (colours): a value that is not finite, or that float32 cannot hold
  /// (beyond 3.40282347e+38). A glTF output checks this before the run.
  /// @throws InputError "<file>: ... not writable as a glTF: <element> ..." naming the element
  ///         as the file has it (an OBJ's line, a PLY's vertex or face, a glTF's primitive and
  ///         element)
  void require_gltf_values() const;
  /// The file's normal groups by simulation face corner (CornerNormalGroups); empty when the
  /// file has no normals (then every vertex has one smooth normal, as a mesh without a document).
  /// @pre matches(mesh)
  CornerNormalGroups normal_groups(const Mesh& mesh) const;
  /// The material of each simulation face and the material libraries (OBJ), or the texture
  /// files and each face's (PLY: its `texnumber`, else the first), or a glTF's materials and
  /// each face's primitive's; empty for an OBJ with no usemtl line, a PLY with no TextureFile
  /// comment, a glTF without materials.
  /// @pre matches(mesh)
  FaceMaterials face_materials(const Mesh& mesh) const;

 protected:
  /// The polygon each simulation face comes from: face i < #polygons is polygon i (its first
  /// triangle), further triangles of split polygons follow in polygon order (read_input_mesh).
  std::vector<std::size_t> face_origins() const;
  /// Per file corner its normal group (CornerNormalGroups; -1: none), for normal_groups; empty:
  /// the file has no normals. An OBJ: its `vn` value's group among the corners of its welded
  /// vertex (mesh/obj_normals.hpp); a PLY's or glTF's per-vertex normals: the normal group of
  /// the corner's vertex among its welded copies (mesh/normal_groups.hpp).
  virtual std::vector<long long> corner_normal_groups(const Mesh& mesh) const {
    (void)mesh;
    return {};
  }

  /// Where texture coordinate `uv` (an index into uv_) and vertex `v` are in the file, for
  /// require_gltf_values' messages ("line 12", "vertex 3").
  virtual std::string uv_place(std::size_t uv) const {
    return "texture coordinate " + std::to_string(uv);
  }
  virtual std::string vertex_place(std::size_t v) const { return "vertex " + std::to_string(v); }

  std::string file_name_;  ///< the file, for messages
  std::size_t vertex_count_ = 0;
  /// Per file vertex its colour (CornerColours::rgba); empty: none.
  std::vector<std::array<double, 4>> colour_;
  int colour_channels_ = 0;                 ///< 3 or 4 with colour_
  std::vector<std::size_t> polygon_start_;  ///< polygon p's corners are [start[p], start[p + 1])
  std::vector<std::size_t> corner_vertex_;  ///< 0-based vertex index of each corner
  std::vector<long long> corner_uv_;        ///< index into uv_ of each corner; -1 none
  std::vector<std::array<double, 2>> uv_;   ///< the file's texture coordinates
  std::vector<int> polygon_material_;       ///< per polygon: index into materials_.names; -1 none
  FaceMaterials materials_;                 ///< names, libraries, source (face_material unused)
};

/// The document of an OBJ, PLY, .glb or .gltf file (by extension); nullptr for OFF and STL, which
/// hold nothing besides positions and faces.
/// @throws InputError naming the file and line if it cannot be read as a document
std::unique_ptr<MeshDocument> read_mesh_document(const std::string& path);

/// `run`'s rule for its input's document (read_mesh_document; null: none, unreadable, or not the
/// mesh simulated) where a result needs one: a .glb or .gltf result (`output_ext`, lower case, no
/// dot) is the input with new positions, so it needs the document; that result and a --gltf
/// animation (`gltf_animation`) hold its texture coordinates and colours as float32
/// (MeshDocument::require_gltf_values). `why_none`: why `document` is null, for the message.
/// @throws InputError naming `input`, before the run (exit 2 in `run`)
void require_run_document(const std::string& input, const MeshDocument* document,
                          const std::string& why_none, const std::string& output_ext,
                          bool gltf_animation);

/// What `run INPUT` checks of INPUT before its run, for a result written in INPUT's own format
/// (as each job of a sweep writes it): read_input_mesh's checks, then require_run_document's for
/// its document. The sweep checks each mesh with it before any job runs.
/// @throws what read_input_mesh throws, and InputError as require_run_document
void check_run_input(const std::string& path);

/// An OBJ file's bytes as a document (src/mesh/obj_document.cpp): every line but `v` and `vn`
/// is written back verbatim; `v` lines get the new positions (anything after x y z, such as
/// vertex colours, kept); `vn` lines get the normals of the new positions; the names of `mtllib`
/// lines are rewritten for a file in another folder (text_for).
/// @param name the file's name, for messages
/// @param path the file the bytes are (read_mesh_document: `name`), whose folder its relative
///             mtllib paths start from (text_for); empty: unknown, text_for writes them as read
/// @throws InputError "<name>: <problem>: line <n> ..." for a line it cannot read
std::unique_ptr<MeshDocument> parse_obj_document(const std::string& name, const std::string& bytes,
                                                 const std::string& path = {});

/// A PLY file's bytes as a document (src/mesh/ply_document.cpp): header and every element byte
/// for byte, but the vertices' x, y, z, written in their declared types and the file's format.
/// Its `comment TextureFile` lines (relative paths from `name`'s folder) are its face_materials.
/// @throws InputError "<name>: <problem>: ..." for a file it cannot read
std::unique_ptr<MeshDocument> parse_ply_document(const std::string& name, const std::string& bytes);

/// A glTF file's bytes as a document (src/mesh/gltf_document.cpp): the file serialized again by
/// tinygltf with each vertex's new position, in its primitive's node space (nodes, materials,
/// textures, texture coordinates kept), and new normals where the primitive has float normals.
/// Its vertices and triangles are read_input_mesh's (before welding). A mesh drawn by several
/// nodes is written once per node: every node after the first gets a copy of the mesh with its
/// own POSITION (and written NORMAL) accessors (docs/design/attributes.md, "glTF inputs").
/// @param binary write a .glb (format() "glb"); else a .gltf with its buffers embedded ("gltf")
/// @throws InputError for a file read_input_mesh refuses, one whose NORMAL or TEXCOORD_0 count
///         is not its POSITION's, or a node transform without an inverse
std::unique_ptr<MeshDocument> parse_gltf_document(const std::string& name, const std::string& bytes,
                                                  bool binary);

/// Writes doc.text_for(path, x, warnings) to `path` atomically (write_text_atomic): an OBJ
/// written to another folder than its input's names the same material libraries.
/// @param warnings where the warnings go (a material library that does not exist); may be null
/// @throws UsageError if the file cannot be written
void write_mesh_document_atomic(const std::string& path, const MeshDocument& doc,
                                const Positions& x, std::vector<std::string>* warnings = nullptr);

/// The shortest text that reads back to exactly v (std::to_chars); used by the documents.
std::string format_double(double v);

}  // namespace shellcontract
