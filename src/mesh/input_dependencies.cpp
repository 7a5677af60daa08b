#include "mesh/input_dependencies.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <new>
#include <optional>
#include <set>

#include "export/gltf_material.hpp"
#include "mesh/file_key.hpp"
#include "mesh/file_safety.hpp"
#include "mesh/formats.hpp"
#include "mesh/gltf_model.hpp"
#include "mesh/line_tokens.hpp"
#include "mesh/obj_material_paths.hpp"
#include "mesh/output_check.hpp"
#include "mesh/ply_header.hpp"
#include "mesh/ply_textures.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

std::string line_text(std::size_t line) { return "line " + std::to_string(line); }

void obj_dependencies(const std::string& path, const std::string& bytes,
                      std::vector<InputDependency>& out) {
  // The statements as the document reads them (obj_document.cpp): continued lines joined.
  std::string joined;
  if (bytes.find('\\') != std::string::npos) {
    joined = bytes;
    join_continued_lines(joined, bytes.find('\n') == std::string::npos ? '\r' : '\n');
  }
  const std::string& text = joined.empty() ? bytes : joined;
  const fs::path folder = fs::path(path).parent_path();
  // Each library once, where it is first named: its images are the same whichever line names
  // it, and a file that names one large library a thousand times must not read it a thousand
  // times. Any other spelling of it is the same file to the output check (output_check.cpp).
  std::set<std::string> seen;
  for (const MtllibLine& l : find_mtllib_lines(bytes, text))
    for (const MtllibName& n : mtllib_names(text, l, folder)) {
      const std::string library = (folder / n.name).string();
      if (!seen.insert(file_key(library)).second) continue;
      out.push_back({library, "the material library that " + quoted_path(path) +
                                  " reads (mtllib, " + line_text(l.line) + ")"});
      for (const MtlTextureFile& t : mtl_texture_files(library))
        out.push_back({t.path, "an image that " + quoted_path(library) +
                                   ", the material library of " + quoted_path(path) + ", names (" +
                                   t.key + ", " + line_text(t.line) + ")"});
    }
}

void ply_dependencies(const std::string& path, const std::string& bytes,
                      std::vector<InputDependency>& out) {
  const ply::Header header = ply::read_ply_header(path, bytes);
  const FaceMaterials m = ply::texture_materials(path, header.comments);
  for (const FaceMaterials::Texture& t : m.textures)
    if (!t.path.empty())
      out.push_back({t.path, "the texture that " + quoted_path(path) +
                                 " names (comment TextureFile, header " + line_text(t.line) + ")"});
}

void gltf_dependencies(const std::string& path, const std::string& bytes,
                       std::vector<InputDependency>& out) {
  std::vector<std::string> looked_up;
  std::optional<tinygltf::Model> model;
  try {
    model = gltf::load_model(path, bytes, &looked_up);
  } catch (const InputError&) {
    // The reader refuses the file later; the paths asked about so far stay.
  }
  for (const std::string& p : looked_up)
    out.push_back({p, "a file that " + quoted_path(path) + " reads (an external buffer)"});
  if (!model) return;
  // Images are not read (no decoding: TINYGLTF_NO_EXTERNAL_IMAGE), but a viewer of the input
  // and of a .gltf result (the input with new positions) loads them from the file's folder.
  const fs::path folder = fs::path(path).parent_path();
  for (std::size_t i = 0; i < model->images.size(); ++i) {
    const std::string& uri = model->images[i].uri;
    if (uri.empty() || uri.rfind("data:", 0) == 0) continue;
    const std::string what =
        "an image that " + quoted_path(path) + " names (images[" + std::to_string(i) + "].uri)";
    out.push_back({(folder / percent_decoded(uri)).string(), what});
    // A URI's path ends at its query or fragment (RFC 3986): a web viewer loads "tex.png" for
    // "tex.png?v=1" or "tex.png#x", so that file is the image too (it had been left unguarded).
    const std::size_t end = uri.find_first_of("?#");
    if (end != std::string::npos && end > 0)
      out.push_back({(folder / percent_decoded(uri.substr(0, end))).string(), what});
  }
}

}  // namespace

std::vector<InputDependency> input_dependencies(const std::string& path) {
  const MeshFormat* format = mesh_format_of(path);
  if (!format || !format->names_files) return {};
  std::vector<InputDependency> out;
  try {
    const std::string bytes = read_regular_file(path);
    switch (format->id) {
      case FormatId::Obj:
        obj_dependencies(path, bytes, out);
        break;
      case FormatId::Ply:
        ply_dependencies(path, bytes, out);
        break;
      case FormatId::Glb:
      case FormatId::Gltf:
        gltf_dependencies(path, bytes, out);
        break;
      case FormatId::Off:
      case FormatId::Stl:
        break;  // names no file (names_files is false)
    }
  } catch (const InputError&) {
    // Missing, not a regular file, a bad PLY header: the reader says why, before any output.
  } catch (const std::bad_alloc&) {
    // The reader reports it, naming the input.
  }
  return out;
}

std::string percent_decoded(const std::string& uri) {
  const auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  std::string s;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
      s += static_cast<char>(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
      i += 2;
    } else {
      s += uri[i];
    }
  }
  return s;
}

}  // namespace shellcontract
