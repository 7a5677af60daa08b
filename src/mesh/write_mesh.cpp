// Writing meshes and text atomically (architecture.md, data flow: ... -> write) with CGAL's writers at
// 17 significant digits, so that a written double reads back bitwise (full precision).
#include <CGAL/IO/OBJ.h>
#include <CGAL/IO/OFF.h>
#include <CGAL/IO/PLY.h>
#include <CGAL/IO/STL.h>
#include <CGAL/Surface_mesh/IO/PLY.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <locale>
#include <sstream>
#include <stdexcept>
#include <streambuf>
#include <string>
#include <utility>
#include <vector>

#include "mesh/eigen_point_map.hpp"
#include "mesh/file_safety.hpp"
#include "mesh/formats.hpp"
#include "mesh/output_target.hpp"
#include "mesh/soup_geometry.hpp"
#include "mesh/soup_writer.hpp"
#include "mesh/stl_positions.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/file_error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/output_files.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

/// "cannot write 'PATH': WHY", with the errno of the call that failed.
[[noreturn]] void cannot_write(const std::string& path, int error_number, const std::string& why) {
  throw OutputFileError("cannot write '" + printable(path) + "': " + why, error_number, path);
}

}  // namespace

// An existing target that is not a regular file is never replaced: as root, --log /dev/null
// would otherwise turn /dev/null into a file.
void refuse_special_output(const std::string& path) {
  // A NUL byte would make stat look at another path; the writer's require_usable_path says why.
  if (path.find('\0') != std::string::npos) return;
  // A descriptor (/dev/stdout, /dev/fd/N) is written into, never replaced, whatever it is.
  if (resolve_output(path).kind == OutputTarget::Kind::STREAM) return;
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode)) return;
  if (S_ISDIR(st.st_mode)) cannot_write(path, EISDIR, "it is a folder");
  // Refused for what it is, not by a failed call: a file error without an errno.
  cannot_write(path, FileSystemFailure::NO_ERRNO,
               "it exists and is not a regular file (a device, FIFO or socket is never replaced)");
}

namespace {

// ------------------------------------------------------------------------------------ writing

/// The stream's double formatting for the writers. CGAL's writers print every coordinate with
/// operator<<, and libstdc++'s num_put formats a double through printf, several times slower
/// than std::to_chars, which gives the same characters (C++17: general format with a precision
/// is printf's %g in the C locale). A frame sequence writes a file per frame, so this matters
/// (run --export-every 1 on bear); anything but plain default formatting goes to the base.
class ToCharsDoublePut : public std::num_put<char> {
 protected:
  iter_type do_put(iter_type out, std::ios_base& str, char_type fill, double v) const override {
    if ((str.flags() & (std::ios_base::floatfield | std::ios_base::showpoint | std::ios_base::showpos |
                        std::ios_base::uppercase)) != 0 ||
        str.width() > 0)
      return std::num_put<char>::do_put(out, str, fill, v);
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general,
                                 static_cast<int>(str.precision()));
    return std::copy(buf, r.ptr, out);
  }
};

/// Writes through `fill` into memory first, then the whole into the file (write_file_atomic).
/// CGAL's writers end every line with std::endl, and a flush per line to a file costs a system
/// call each (one write per file instead). A throwing `fill` leaves no file behind. `binary` sets
/// the stream's CGAL mode, which CGAL's PLY and STL writers follow.
void write_atomic(const std::string& path, const std::function<void(std::ostream&)>& fill, bool binary = false) {
  // The classic locale, whatever the host's global one (core/classic_locale.hpp): CGAL's writers
  // print counts and indices with operator<< too, and a host's numpunct grouped them ("13.826").
  // The locale owns the facet.
  std::ostringstream text;
  text.imbue(std::locale(std::locale::classic(), new ToCharsDoublePut));
  CGAL::IO::set_mode(text, binary ? CGAL::IO::BINARY : CGAL::IO::ASCII);
  fill(text);
  const std::string bytes = std::move(text).str();
  write_file_atomic(path, [&](std::ostream& out) {
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  });
}

/// Enough significant digits that every double reads back bitwise (max_digits10).
constexpr int FULL_PRECISION = 17;

/// Removed elements or a row count that differs from the vertex count would index past x.
void check_positions(const Mesh& mesh, const Positions& x, const char* who) {
  if (mesh.has_garbage())
    throw std::invalid_argument(std::string(who) + ": the mesh has removed elements; call collect_garbage() first");
  if (static_cast<std::size_t>(x.rows()) != mesh.number_of_vertices())
    throw std::invalid_argument(std::string(who) + ": " + std::to_string(x.rows()) + " position rows for " +
                                std::to_string(mesh.number_of_vertices()) + " vertices");
}

/// mesh_for_output of a welded mesh: the input's vertices (x expanded by input_positions) and
/// faces, in order, each face from its first input corner. The input as given is a polygon mesh
/// with boundary (weld_seams checked it with CGAL), which soup_mesh builds.
Mesh input_mesh_for_output(const Mesh& mesh, const Positions& x) {
  if (mesh.has_garbage())
    throw std::invalid_argument("mesh_for_output: the mesh has removed elements; call collect_garbage() first");
  const Positions in = input_positions(mesh, x);
  std::vector<Point3> points;
  points.reserve(static_cast<std::size_t>(in.rows()));
  for (Eigen::Index i = 0; i < in.rows(); ++i) points.emplace_back(in(i, 0), in(i, 1), in(i, 2));
  std::vector<std::vector<std::size_t>> faces;
  faces.reserve(mesh.number_of_faces());
  for (const auto& f : input_faces(mesh)) faces.emplace_back(f.begin(), f.end());
  return soup::soup_mesh(points, faces, "mesh_for_output");
}

}  // namespace

// ================================================================================== writing

Mesh mesh_for_output(const Mesh& mesh, const Positions& x) {
  if (has_welded_seams(mesh)) return input_mesh_for_output(mesh, x);
  check_positions(mesh, x, "mesh_for_output");
  // A copy keeps every face's halfedge, so each face lists its corners from the same vertex as
  // the input (per-corner data such as UVs stay aligned); the maps go, the caller adds its own.
  Mesh out = mesh;
  out.remove_all_property_maps();
  for (const VertexIndex v : out.vertices()) {
    const auto i = static_cast<Eigen::Index>(v.idx());
    out.point(v) = Point3(x(i, 0), x(i, 1), x(i, 2));
  }
  return out;
}

void write_ply_atomic(const std::string& path, const Mesh& mesh, const std::string& comments, bool binary) {
  if (mesh.has_garbage())
    throw std::invalid_argument("write_ply_atomic: the mesh has removed elements; call collect_garbage() first");
  write_atomic(path, [&](std::ostream& out) {
    if (!CGAL::IO::write_PLY(out, mesh, comments, CGAL::parameters::stream_precision(FULL_PRECISION)))
      throw UsageError("cannot write '" + path + "': CGAL's PLY writer failed");
  }, binary);
}

namespace {

/// The writers' formats, named by the path's extension; the message says what is wrong with
/// the name (none, another format's) rather than "unknown extension '.'". A folder, device or
/// FIFO in the output's place was refused before (refuse_special_output), for what it is.
FormatId require_plain_mesh_extension(const std::string& path, const std::string& ext) {
  const MeshFormat* format = find_mesh_format(ext);
  if (format && format->plain_writer) return format->id;
  throw UsageError(
      "cannot write '" + path + "': " +
      (ext.empty() ? "the file name has no extension" : "unknown extension '." + ext + "'") +
      " (expected " + extension_list(&MeshFormat::plain_writer) + ")");
}

/// write_mesh_atomic once the STL's positions are checked; `mesh` not welded.
void write_plain_mesh(const std::string& path, const std::string& ext, const Mesh& mesh,
                      const Positions& x, bool binary) {
  check_positions(mesh, x, "write_mesh_atomic");
  // A NaN or an infinity would be written as "nan" or "inf": a file that no reader, ours
  // included, takes back.
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    if (!x.row(i).allFinite())
      throw std::invalid_argument("write_mesh_atomic: vertex " + std::to_string(i) +
                                  " has a coordinate that is not finite; nothing written to '" + path + "'");
  const FormatId format = require_plain_mesh_extension(path, ext);
  if (format == FormatId::Ply) {
    // CGAL 5.5's Surface_mesh PLY writer takes the mesh's own points (no vertex_point_map).
    write_ply_atomic(path, mesh_for_output(mesh, x), "", binary);
    return;
  }
  // The other writers read the positions through the point map: no mesh copy. They write
  // vertices and faces in index order, each face from its halfedge's target, as read back.
  const auto np = CGAL::parameters::vertex_point_map(EigenPointMap(x)).stream_precision(FULL_PRECISION);
  write_atomic(
      path,
      [&](std::ostream& out) {
        bool ok = false;
        switch (format) {
          case FormatId::Off:
            ok = CGAL::IO::write_OFF(out, mesh, np);
            break;
          case FormatId::Obj:
            ok = CGAL::IO::write_OBJ(out, mesh, np);
            break;
          case FormatId::Ply:
            break;             // written above
          case FormatId::Stl:  // binary when the stream's mode says so
            ok = CGAL::IO::write_STL(out, mesh, np);
            break;
          case FormatId::Glb:
          case FormatId::Gltf:
            break;  // no plain writer: refused above
        }
        if (!ok) throw UsageError("cannot write '" + path + "': CGAL's ." + ext + " writer failed");
      },
      binary && find_mesh_format(ext)->binary_writer);
}

}  // namespace

void write_mesh_atomic(const std::string& path, const Mesh& mesh, const Positions& x, bool binary) {
  // What the path is (a device, a FIFO, a folder) says more than its name does: /dev/null, which
  // has no extension, is refused as a device, not for its name.
  refuse_special_output(path);
  const std::string ext = lower_extension(path);
  // Checked on the mesh as given, before a welded mesh's copies are made: copies of one vertex
  // may share a position (read back, they are that vertex), two vertices may not.
  if (ext == "stl") {
    if (!has_welded_seams(mesh)) check_positions(mesh, x, "write_mesh_atomic");
    require_distinct_stl_positions("cannot write '" + path + "'", mesh, x, binary);
  }
  if (has_welded_seams(mesh)) {
    // The input's vertices and faces, each copy at its vertex's position: a mesh of its own.
    const Mesh out = input_mesh_for_output(mesh, x);
    write_plain_mesh(path, ext, out, positions_from_mesh(out), binary);
    return;
  }
  write_plain_mesh(path, ext, mesh, x, binary);
}

void write_polygon_soup_atomic(const std::string& path, const std::vector<Point3>& points,
                               const std::vector<std::vector<std::size_t>>& polygons, bool binary) {
  refuse_special_output(path);  // before the extension, as write_mesh_atomic
  const std::string ext = lower_extension(path);
  const FormatId format = require_plain_mesh_extension(path, ext);
  for (const auto& p : polygons) {
    if (format == FormatId::Stl && p.size() != 3)
      throw std::invalid_argument("write_polygon_soup_atomic: an STL file holds triangles only");
    for (const std::size_t v : p)
      if (v >= points.size()) throw std::invalid_argument("write_polygon_soup_atomic: a polygon names a missing point");
  }
  const auto np = CGAL::parameters::stream_precision(FULL_PRECISION);
  write_atomic(
      path,
      [&](std::ostream& out) {
        bool ok = false;
        switch (format) {
          case FormatId::Off:
            ok = CGAL::IO::write_OFF(out, points, polygons, np);
            break;
          case FormatId::Obj:
            ok = CGAL::IO::write_OBJ(out, points, polygons, np);
            break;
          case FormatId::Ply:
            ok = CGAL::IO::write_PLY(out, points, polygons, np);
            break;
          case FormatId::Stl:
            ok = CGAL::IO::write_STL(out, points, polygons, np);
            break;
          case FormatId::Glb:
          case FormatId::Gltf:
            break;  // no plain writer: refused above
        }
        if (!ok) throw UsageError("cannot write '" + path + "': CGAL's ." + ext + " writer failed");
      },
      binary && find_mesh_format(ext)->binary_writer);
}

void write_text_atomic(const std::string& path, const std::string& text) {
  write_file_atomic(path, [&](std::ostream& out) {
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
  });
}

namespace {

/// An output stream buffer over a file descriptor that keeps the first write error's errno, so
/// that a full disk is reported as such whatever the writer on top of it makes of the failure.
class FdBuf final : public std::streambuf {
 public:
  explicit FdBuf(int fd) : fd_(fd), buffer_(BUFFER_BYTES) { setp(buffer_.data(), buffer_.data() + BUFFER_BYTES); }
  int error() const { return error_; }
  std::uint64_t written() const { return written_; }

 protected:
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (n < static_cast<std::streamsize>(BUFFER_BYTES)) return std::streambuf::xsputn(s, n);
    if (!drain() || !put(s, static_cast<std::size_t>(n))) return 0;  // large pieces go straight out
    return n;
  }
  int sync() override { return drain() ? 0 : -1; }
  /// tellp(): the bytes written so far (the glTF writer reports its size through it).
  pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) override {
    if (off != 0 || dir != std::ios_base::cur || !(which & std::ios_base::out)) return pos_type(off_type(-1));
    return pos_type(static_cast<off_type>(written_ + static_cast<std::uint64_t>(pptr() - pbase())));
  }

 private:
  bool drain() {
    const std::size_t n = static_cast<std::size_t>(pptr() - pbase());
    setp(buffer_.data(), buffer_.data() + BUFFER_BYTES);
    return put(buffer_.data(), n);
  }
  bool put(const char* s, std::size_t n) {
    if (error_) return false;
    while (n > 0) {
      const ssize_t w = ::write(fd_, s, n);
      if (w < 0) {
        if (errno == EINTR) continue;
        error_ = errno;
        return false;
      }
      s += w;
      n -= static_cast<std::size_t>(w);
      written_ += static_cast<std::uint64_t>(w);
    }
    return true;
  }
  int fd_;
  int error_ = 0;
  std::uint64_t written_ = 0;
  static constexpr std::size_t BUFFER_BYTES = 8192;  // as std::ofstream's; large pieces bypass it
  std::vector<char> buffer_;
};

}  // namespace

namespace {

/// A descriptor named by the output path (/dev/stderr with stderr redirected to a file): written
/// straight into at its own offset, as `echo >&2` would, never replaced. The whole text is made
/// first, so a writer that throws writes nothing there.
void write_stream(const std::string& path, int fd,
                  const std::function<void(std::ostream&)>& write) {
  int error = 0;
  const std::string why = stream_problem(fd, error);
  if (!why.empty()) cannot_write(path, error, why);
  std::ostringstream text;
  text.imbue(std::locale::classic());
  write(text);
  const std::string bytes = std::move(text).str();
  FdBuf buf(fd);
  std::ostream out(&buf);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.flush();
  if (buf.error()) cannot_write(path, buf.error(), file_error_text(buf.error()));
}

}  // namespace

void write_file_atomic(const std::string& given, const std::function<void(std::ostream&)>& write) {
  require_usable_path(given, "output");
  // A symbolic link is followed: its target is replaced and the link kept; a descriptor is
  // written into (docs/design/output-safety.md, "Symbolic links and streams"). Before, the link
  // itself was replaced: as root, --log /dev/stderr with stderr redirected to a file turned the
  // system's /dev/stderr into a plain file.
  const OutputTarget resolved = resolve_output(given);
  if (!resolved.problem.empty()) cannot_write(given, resolved.error, resolved.problem);
  if (resolved.kind == OutputTarget::Kind::STREAM) return write_stream(given, resolved.fd, write);
  const std::string& path = resolved.path;
  refuse_special_output(path);
  const fs::path target(path);
  const std::string dir = target.has_parent_path() ? target.parent_path().string() : std::string(".");
  // Same folder, so that rename is atomic (same file system). The name is random and created
  // exclusively (never an existing file, never through a link planted there), and registered in
  // the same step, so that SIGINT and SIGTERM remove it at any moment (file_safety.hpp).
  const RegisteredTemporary tmp = create_registered_temporary(dir, target.filename().string() + ".tmp");
  if (tmp.fd < 0) {
    const int e = errno;
    cannot_write(
        given, e,
        "cannot create a file in the folder '" + printable(dir) + "' (" + file_error_text(e) + ")");
  }
  const int slot = tmp.slot;
  const auto discard = [&] {
    ::unlink(tmp.path.c_str());
    unregister_temporary(slot);
  };
  int error = 0;
  // A file replaced keeps its permissions (a private 0600 result stays private); a new one gets
  // the temporary's, 0666 less the umask. Best effort: a file system without modes (FAT) refuses
  // fchmod, and the result is still written.
  // Its owner and group are kept too where the caller may set them (root replacing a user's
  // result, which the user could no longer read as root's 0640 file; a user's file of one of
  // their groups): chown before chmod, which chown's clearing of set-user-ID bits would undo.
  struct stat before {};
  if (::stat(path.c_str(), &before) == 0 && S_ISREG(before.st_mode)) {
    if (::fchown(tmp.fd, before.st_uid, before.st_gid) != 0)
      (void)::fchown(tmp.fd, static_cast<uid_t>(-1), before.st_gid);
    (void)::fchmod(tmp.fd, before.st_mode & 07777);
  }
  {
    FdBuf buf(tmp.fd);
    std::ostream out(&buf);
    out.imbue(std::locale::classic());  // numbers as in every file, whatever the host's locale
    try {
      write(out);
      out.flush();
    } catch (...) {
      ::close(tmp.fd);
      discard();
      // A writer that gave up because the disk did (tinygltf: "serializing failed") is
      // reported by the disk's reason.
      if (buf.error()) cannot_write(given, buf.error(), file_error_text(buf.error()));
      throw;
    }
    error = buf.error();
    if (!error && !out) error = EIO;
  }
  if (::close(tmp.fd) != 0 && !error) error = errno;  // NFS reports some write errors here
  if (error) {
    discard();
    cannot_write(given, error, file_error_text(error));
  }
  if (std::rename(tmp.path.c_str(), path.c_str()) != 0) {
    const int e = errno;
    discard();
    cannot_write(given, e, file_error_text(e));
  }
  unregister_temporary(slot);
}

}  // namespace shellcontract
