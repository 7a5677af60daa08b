// Loading a glTF 2.0 file's model with tinygltf (gltf::load_model, gltf_model.hpp): the .glb
// container and the JSON checked before tinygltf parses them, and tinygltf's file callbacks,
// so that an external buffer is read as the mesh file itself is and a refusal names its file.
// Apart from gltf_reader.cpp, which turns the model into the soup of triangles.
#include <sys/stat.h>

#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "mesh/file_safety.hpp"
#include "mesh/gltf_json_checks.hpp"
#include "mesh/gltf_model.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/file_error.hpp"

namespace shellcontract {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem,
                       const std::string& details) {
  throw InputError(path + ": " + problem + ": " + details);
}

std::uint32_t le32(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i)
    v = (v << 8) | static_cast<unsigned char>(b[at + static_cast<std::size_t>(i)]);
  return v;
}

/// The GLB container, checked before tinygltf sees it: tinygltf accepts a header length short of
/// the file and reads a BIN chunk's 8-byte header past a length that only covers its data, and
/// its messages say "Invalid glTF binary." without saying what is wrong.
void check_glb_container(const std::string& path, const std::string& b) {
  if (b.size() < 12)
    fail(path, "truncated .glb",
         "the file has " + std::to_string(b.size()) + " bytes, less than the 12-byte header");
  if (b.compare(0, 4, "glTF") != 0)
    fail(path, "not a binary glTF", "the file does not start with the magic 'glTF'");
  const std::uint32_t version = le32(b, 4), length = le32(b, 8);
  if (version != 2)
    fail(path, "unsupported glTF version",
         "the header says version " + std::to_string(version) + " (only 2 is read)");
  if (length != b.size())
    fail(path, length > b.size() ? "truncated .glb" : "bytes after the .glb's end",
         "the header says " + std::to_string(length) + " bytes, the file has " +
             std::to_string(b.size()));
  std::size_t at = 12;
  for (int chunk = 0; at < b.size(); ++chunk) {
    if (b.size() - at < 8)
      fail(path, "truncated .glb",
           "chunk " + std::to_string(chunk) + " at byte " + std::to_string(at) +
               " has no complete 8-byte header");
    const std::uint64_t n = le32(b, at);
    const std::uint32_t type = le32(b, at + 4);
    if (n > b.size() - at - 8)
      fail(path, "truncated .glb",
           "chunk " + std::to_string(chunk) + " at byte " + std::to_string(at) + " declares " +
               std::to_string(n) + " bytes, " + std::to_string(b.size() - at - 8) + " remain");
    if (chunk == 0 && type != 0x4E4F534Au) fail(path, "bad .glb", "the first chunk is not JSON");
    at += 8 + n;
  }
}

// tinygltf's file callbacks: an external buffer is read like the mesh file itself (a regular file,
// every read checked: read_regular_file), and a path is never expanded by the shell's rules
// (tinygltf's default ExpandFilePath calls wordexp) nor opened to test that it exists (fopen on a
// FIFO blocks).
/// The callbacks' user data: the paths asked about and why the file system refused them, so
/// that a glTF whose buffer cannot be had is a file error about the buffer (Python's
/// FileNotFoundError naming the .bin), not about the .gltf.
struct ExternalFiles {
  /// When given, every path asked about, found or not (input_dependencies).
  std::vector<std::string>* looked_up = nullptr;
  /// Each path not found or not read, with its errno, in the order asked.
  std::vector<FileSystemFailure> refused;
  /// The buffers the JSON declares (check_top_level), to bound an external buffer's read.
  std::vector<gltf::DeclaredBuffer> declared;
  /// The files read, by device and inode (a path, a link to it, "./" before it: one file).
  std::set<std::pair<dev_t, ino_t>> read;
  /// The refusal of a buffer file larger than its buffer, or read already, made before reading it.
  std::string too_large;
};

/// Buffer indices for a message: "0, 1, 2, ..., 999 (1000 buffers)".
std::string listed(const std::vector<std::size_t>& buffers) {
  std::string out;
  for (std::size_t k = 0; k < buffers.size() && k < 3; ++k)
    out += (k ? ", " : "") + std::to_string(buffers[k]);
  if (buffers.size() > 3) out += ", ..., " + std::to_string(buffers.back());
  return out + " (" + std::to_string(buffers.size()) + " buffers)";
}

bool file_exists(const std::string& p, void* files) {
  auto& f = *static_cast<ExternalFiles*>(files);
  if (f.looked_up) f.looked_up->push_back(p);
  struct stat st {};
  if (::stat(p.c_str(), &st) == 0) return true;
  const int error_number = errno;
  f.refused.emplace_back(error_number, p);
  return false;
}
std::string same_path(const std::string& p, void*) { return p; }
bool read_buffer_file(std::vector<unsigned char>* out, std::string* err, const std::string& p,
                      void* files) {
  try {
    auto& f = *static_cast<ExternalFiles*>(files);
    const auto [bound, why] = gltf::buffer_file_bound(f.declared, p);
    const std::uint64_t size = regular_file_size(p);  // a folder, device or FIFO refused as before
    if (size > bound) {
      f.too_large = "buffer file too large: '" + printable(p) + "' has " + std::to_string(size) +
                    " bytes, more than " + why + "; it was not read";
      if (err) *err += f.too_large;
      return false;
    }
    // Each buffer holds a copy of its file: a small JSON naming one large file in many buffers
    // would cost the file's size as many times. A file is read once per load, so that what a
    // load reads is bounded by the sizes of the files it names.
    struct stat st {};
    if (::stat(p.c_str(), &st) == 0) {
      const std::pair<dev_t, ino_t> id{st.st_dev, st.st_ino};
      if (!f.read.insert(id).second) {
        f.too_large = "buffer file read twice: '" + printable(p) + "' (" + std::to_string(size) +
                      " bytes) is named by buffers " + listed(gltf::buffers_naming(f.declared, p)) +
                      ", and a file is read once (each buffer would hold a copy of its own); let "
                      "one buffer hold it and buffer views share that buffer";
        if (err) *err += f.too_large;
        return false;
      }
    }
    const std::string b = read_regular_file(p, bound);
    out->assign(b.begin(), b.end());
    return true;
  } catch (const std::exception& e) {
    if (const auto* failure = dynamic_cast<const FileSystemFailure*>(&e))
      static_cast<ExternalFiles*>(files)->refused.push_back(*failure);
    if (err) *err += e.what();
    return false;
  }
}

/// The refusal that ended a load whose error ends with `last_line`: a buffer tinygltf did not
/// find ("File not found : URI", looked for first in `dir`, the name the glTF gives it) or
/// could not read ("File read error : PATH : ..."). A buffer ends the load at once, so its
/// line is the last; an image missing earlier only warns, and is never the one returned.
const FileSystemFailure* buffer_refusal(const ExternalFiles& files, const std::string& dir,
                                        const std::string& last_line) {
  static const std::string NOT_FOUND = "File not found : ", READ_ERROR = "File read error : ";
  std::string path;
  if (last_line.rfind(NOT_FOUND, 0) == 0) {
    const std::string uri = last_line.substr(NOT_FOUND.size());
    // tinygltf's JoinPath: the folder, a '/' unless it ends with one, the URI.
    path = dir.empty() ? uri : dir + (dir.back() == '/' ? "" : "/") + uri;
  } else if (last_line.rfind(READ_ERROR, 0) == 0) {
    const std::size_t end = last_line.find(" : ", READ_ERROR.size());
    if (end == std::string::npos) return nullptr;
    path = last_line.substr(READ_ERROR.size(), end - READ_ERROR.size());
  } else {
    return nullptr;
  }
  for (auto it = files.refused.rbegin(); it != files.refused.rend(); ++it)
    if (it->path() == path) return &*it;
  return nullptr;
}
bool no_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "writing is not done by the reader";
  return false;
}
/// Images are never decoded. One in a buffer view stays there; one in a data URI (tinygltf
/// decodes the base64 and drops the URI) keeps its encoded bytes in `image`, so that the glTF
/// document can write it back (gltf_document.cpp).
bool skip_image(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                const unsigned char* bytes, int size, void*) {
  if (image->bufferView < 0 && bytes && size > 0) image->image.assign(bytes, bytes + size);
  return true;
}

}  // namespace

tinygltf::Model gltf::load_model(const std::string& path, const std::string& bytes,
                                 std::vector<std::string>* looked_up) {
  if (bytes.size() > std::numeric_limits<unsigned int>::max())
    fail(path, "too large", "a glTF file holds at most 4 GiB");
  const bool binary = bytes.compare(0, 4, "glTF") == 0;
  if (binary) check_glb_container(path, bytes);
  // Before any recursive parser sees it: the JSON's depth, then what tinygltf reads leniently.
  const std::size_t json_at = binary ? 20 : 0;
  const std::size_t json_size = binary ? le32(bytes, 12) : bytes.size();
  ExternalFiles files{looked_up, {}, {}, {}, {}};
  files.declared = gltf::check_top_level(path, bytes.data() + json_at, json_size, json_at);
  // In a .glb only buffer 0 may leave out its uri, and is then the BIN chunk (glTF 2.0,
  // "GLB-stored Buffer"); tinygltf made every other such buffer a copy of the chunk, so a
  // thousand of them in a small file's JSON took a thousand times its data.
  if (binary)
    for (std::size_t i = 1; i < files.declared.size(); ++i)
      if (files.declared[i].uri.empty())
        fail(path, "buffer without uri",
             "buffer " + std::to_string(i) +
                 " names no file; in a .glb only buffer 0 may, and is then the BIN chunk");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skip_image, nullptr);
  loader.SetFsCallbacks(
      tinygltf::FsCallbacks{file_exists, same_path, read_buffer_file, no_write, &files});
  tinygltf::Model m;
  std::string err, warn;
  const std::string dir = std::filesystem::path(path).parent_path().string();
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const auto n = static_cast<unsigned int>(bytes.size());
  bool ok = false;
  try {
    ok = binary ? loader.LoadBinaryFromMemory(&m, &err, &warn, data, n, dir)
                : loader.LoadASCIIFromString(&m, &err, &warn, bytes.data(), n, dir);
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {  // nlohmann-json's, for a document it cannot parse
    err += e.what();
  }
  if (!ok && !files.too_large.empty()) throw InputError(path + ": " + files.too_large);
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    const std::size_t last_line = err.rfind('\n');
    const FileSystemFailure* buffer =
        buffer_refusal(files, dir, err.substr(last_line == std::string::npos ? 0 : last_line + 1));
    for (char& c : err)
      if (c == '\n') c = ';';
    const std::string message = path + ": " + (binary ? "cannot read .glb" : "cannot read .gltf") +
                                ": " + (err.empty() ? "tinygltf refused it" : "tinygltf: " + err);
    if (buffer) throw InputFileError(message, buffer->error_number(), buffer->path());
    throw InputError(message);
  }
  return m;
}

}  // namespace shellcontract
