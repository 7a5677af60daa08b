// Writing meshes and text atomically (design.md, data flow: ... -> write). Done by hand for the
// four formats, so that the positions come from a Positions array (no mesh copy), the order is
// exactly the mesh's index order, and doubles are printed with 17 significant digits (lossless
// round trip).
#include <unistd.h>  // getpid, for unique temporary names

#include <algorithm>
#include <array>
#include <cctype>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "shellcontract/core/error.hpp"
#include "shellcontract/mesh/io.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}
// ------------------------------------------------------------------------------------ writing

/// Writes through `fill` into a temporary file next to `path`, then renames it over `path`.
void write_atomic(const std::string& path, const std::function<void(std::ostream&)>& fill) {
  static std::atomic<unsigned> counter{0};
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  // Same folder, so that rename is atomic (same file system); hidden, pid- and counter-unique so
  // that parallel writers never share a temporary.
  const fs::path tmp = dir / ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out)
      throw UsageError("cannot write '" + path + "': cannot create a file in folder '" + dir.string() + "' (" + std::strerror(errno) + ")");
    out << std::setprecision(17);
    try {
      fill(out);
    } catch (...) {
      out.close();
      std::remove(tmp.c_str());
      throw;
    }
    out.flush();
    if (!out) {
      out.close();
      std::remove(tmp.c_str());
      throw UsageError("cannot write '" + path + "': writing the temporary file failed (disk full?)");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp.c_str());
    throw UsageError("cannot write '" + path + "': " + why);
  }
}

std::array<std::size_t, 3> corners(const Mesh& mesh, FaceIndex f) {
  const HalfedgeIndex h = mesh.halfedge(f);
  return {mesh.target(h).idx(), mesh.target(mesh.next(h)).idx(), mesh.target(mesh.next(mesh.next(h))).idx()};
}

}  // namespace

// ================================================================================== writing

void write_mesh_atomic(const std::string& path, const Mesh& mesh, const Positions& x) {
  if (mesh.has_garbage())
    throw std::invalid_argument("write_mesh_atomic: the mesh has removed elements; call collect_garbage() first");
  if (static_cast<std::size_t>(x.rows()) != mesh.number_of_vertices())
    throw std::invalid_argument("write_mesh_atomic: " + std::to_string(x.rows()) + " position rows for " +
                                std::to_string(mesh.number_of_vertices()) + " vertices");
  const std::string ext = lower_extension(path);
  if (ext != "off" && ext != "obj" && ext != "ply" && ext != "stl")
    throw UsageError("cannot write '" + path + "': unknown extension '." + ext + "' (expected .off, .obj, .ply or .stl)");
  const Eigen::Index nv = x.rows();
  const std::size_t nf = mesh.number_of_faces();

  // Formatted with to_chars into one string per file and written at once: the same bytes as the
  // stream at precision 17 (to_chars' general format with a precision is printf's %.17g, which
  // is what the stream uses), several times faster, which matters for frame sequences.
  std::string text;
  text.reserve(static_cast<std::size_t>(nv) * 64 + nf * 24);
  const auto put = [&text](auto value) {
    char buf[32];
    std::to_chars_result r;
    if constexpr (std::is_floating_point_v<decltype(value)>)
      r = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::general, 17);
    else
      r = std::to_chars(buf, buf + sizeof buf, value);
    text.append(buf, r.ptr);
  };
  const auto put3 = [&](const char* prefix, auto a, auto b, auto c) {
    text += prefix;
    put(a);
    text += ' ';
    put(b);
    text += ' ';
    put(c);
    text += '\n';
  };
  const auto vertex_rows = [&](const char* prefix) {
    for (Eigen::Index i = 0; i < nv; ++i) put3(prefix, x(i, 0), x(i, 1), x(i, 2));
  };
  const auto face_rows = [&](const char* prefix, std::size_t base) {
    for (const FaceIndex f : mesh.faces()) {
      const auto c = corners(mesh, f);
      put3(prefix, c[0] + base, c[1] + base, c[2] + base);
    }
  };

  if (ext == "off") {
    text += "OFF\n" + std::to_string(nv) + ' ' + std::to_string(nf) + " 0\n";
    vertex_rows("");
    face_rows("3 ", 0);
  } else if (ext == "obj") {
    text += "# written by shellcontract\n";
    vertex_rows("v ");
    face_rows("f ", 1);  // OBJ counts from 1
  } else if (ext == "ply") {
    // Double properties: a float PLY would lose the positions' precision.
    text += "ply\nformat ascii 1.0\ncomment written by shellcontract\nelement vertex " + std::to_string(nv) +
            "\nproperty double x\nproperty double y\nproperty double z\nelement face " + std::to_string(nf) +
            "\nproperty list uchar int vertex_indices\nend_header\n";
    vertex_rows("");
    face_rows("3 ", 0);
  } else {
    // ASCII STL has no shared vertices: readers merge equal points in order of first
    // appearance, so faces keep their order but vertex numbering may not.
    text += "solid shellcontract\n";
    for (const FaceIndex f : mesh.faces()) {
      const auto c = corners(mesh, f);
      const Vec3 a = x.row(static_cast<Eigen::Index>(c[0])).transpose();
      const Vec3 b = x.row(static_cast<Eigen::Index>(c[1])).transpose();
      const Vec3 d = x.row(static_cast<Eigen::Index>(c[2])).transpose();
      Vec3 n = (b - a).cross(d - a);
      if (n.norm() > 0.0) n.normalize();
      put3("facet normal ", n.x(), n.y(), n.z());
      text += "outer loop\n";
      for (const Vec3* p : {&a, &b, &d}) put3("vertex ", p->x(), p->y(), p->z());
      text += "endloop\nendfacet\n";
    }
    text += "endsolid shellcontract\n";
  }
  write_atomic(path, [&](std::ostream& out) { out.write(text.data(), static_cast<std::streamsize>(text.size())); });
}

void write_text_atomic(const std::string& path, const std::string& text) {
  write_atomic(path, [&](std::ostream& out) { out << text; });
}

}  // namespace shellcontract
