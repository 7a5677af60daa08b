// The input's JSON, updated by what the glTF document changes (gltf_json.hpp).
#include "mesh/gltf_json.hpp"

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <system_error>

#include "mesh/input_dependencies.hpp"
#include "mesh/obj_material_paths.hpp"

namespace shellcontract::gltf {
namespace {

using json = nlohmann::json;

std::uint32_t le32(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t k = 0; k < 4; ++k)
    v |= static_cast<std::uint32_t>(static_cast<unsigned char>(b[at + k])) << (8 * k);
  return v;
}

void put32(std::string& b, std::uint32_t v) {
  for (std::size_t k = 0; k < 4; ++k) b += static_cast<char>((v >> (8 * k)) & 0xFFu);
}

json parse(const std::string& text, const char* whose) {
  json j = json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object())
    throw std::runtime_error(std::string("glTF document: ") + whose + " JSON does not parse");
  return j;
}

/// tinygltf writes an object or array without members as null. No glTF property may be null
/// (and tinygltf's reader drops a null inside extras), so an element taken from tinygltf's JSON
/// gets an empty object there: every glTF property that can be empty is an object.
void nulls_to_objects(json& j) {
  if (j.is_null())
    j = json::object();
  else if (j.is_structured())
    for (json& e : j) nulls_to_objects(e);
}

/// Member `key` of `to` as `from` has it: copied, or removed where `from` has none.
void take(json& to, const json& from, const char* key) {
  if (!to.is_object() || !from.is_object()) return;
  const auto it = from.find(key);
  if (it != from.end())
    to[key] = *it;
  else
    to.erase(key);
}

/// The top-level array `name` (empty where the document has none).
const json& array_of(const json& doc, const char* name) {
  static const json none = json::array();
  const auto it = doc.find(name);
  return it != doc.end() && it->is_array() ? *it : none;
}

/// Every primitive's attributes as `from` has them (tinygltf's JSON of the same mesh).
void take_attributes(json& mesh, const json& from) {
  const auto p = mesh.find("primitives");
  const auto q = from.find("primitives");
  if (p == mesh.end() || q == from.end() || !p->is_array() || !q->is_array()) return;
  for (std::size_t k = 0; k < p->size() && k < q->size(); ++k) take((*p)[k], (*q)[k], "attributes");
}

json merged(const json& in, const json& out, const std::vector<int>& bounded) {
  json doc = in;
  const auto elements = [&](const char* name) -> json& {
    json& a = doc[name];
    if (!a.is_array()) a = json::array();
    return a;
  };
  // Elements of the input, with the members the document changes.
  if (!array_of(in, "buffers").empty()) {
    json& buffers = elements("buffers");
    const json& written = array_of(out, "buffers");
    for (std::size_t i = 0; i < buffers.size() && i < written.size(); ++i) {
      take(buffers[i], written[i], "byteLength");
      take(buffers[i], written[i], "uri");  // the .glb's BIN chunk has none; .gltf: a data URI
    }
  }
  const std::size_t accessors = array_of(in, "accessors").size();
  for (const int a : bounded)
    if (a >= 0 && static_cast<std::size_t>(a) < accessors &&
        static_cast<std::size_t>(a) < array_of(out, "accessors").size())
      for (const char* key : {"min", "max"})
        take(elements("accessors")[static_cast<std::size_t>(a)],
             array_of(out, "accessors")[static_cast<std::size_t>(a)], key);
  const json &nodes_in = array_of(in, "nodes"), &nodes_out = array_of(out, "nodes");
  for (std::size_t i = 0; i < nodes_in.size() && i < nodes_out.size(); ++i)
    take(elements("nodes")[i], nodes_out[i], "mesh");
  const json &meshes_in = array_of(in, "meshes"), &meshes_out = array_of(out, "meshes");
  for (std::size_t i = 0; i < meshes_in.size() && i < meshes_out.size(); ++i)
    take_attributes(elements("meshes")[i], meshes_out[i]);
  // Elements the document appended: a mesh is a copy of the mesh its node drew in the input, the
  // first node (in order) that draws it now and drew an input mesh. Found in one pass over the
  // nodes, not one per appended mesh: a scene of many instances appends a mesh per instance.
  // tinygltf writes a node's mesh as an integer, which the JSON holds as unsigned.
  const std::size_t NONE = static_cast<std::size_t>(-1);
  std::vector<std::size_t> node_of(
      meshes_out.size() - std::min(meshes_in.size(), meshes_out.size()), NONE);
  for (std::size_t i = 0; i < nodes_in.size() && i < nodes_out.size(); ++i) {
    const auto now = nodes_out[i].find("mesh"), was = nodes_in[i].find("mesh");
    if (now == nodes_out[i].end() || was == nodes_in[i].end() || !now->is_number_unsigned() ||
        !was->is_number_unsigned() || was->get<std::size_t>() >= meshes_in.size())
      continue;
    const auto j = now->get<std::size_t>();
    if (j >= meshes_in.size() && j < meshes_out.size() && node_of[j - meshes_in.size()] == NONE)
      node_of[j - meshes_in.size()] = i;
  }
  for (std::size_t j = meshes_in.size(); j < meshes_out.size(); ++j) {
    json mesh = meshes_out[j];
    nulls_to_objects(mesh);
    const std::size_t i = node_of[j - meshes_in.size()];
    if (i != NONE) {
      json copy = meshes_in[nodes_in[i].at("mesh").get<std::size_t>()];
      take(copy, meshes_out[j], "name");
      take_attributes(copy, meshes_out[j]);
      mesh = std::move(copy);
    }
    elements("meshes").push_back(std::move(mesh));
  }
  for (const char* name : {"accessors", "bufferViews", "buffers", "nodes"})
    for (std::size_t i = array_of(in, name).size(); i < array_of(out, name).size(); ++i) {
      json e = array_of(out, name)[i];
      nulls_to_objects(e);
      elements(name).push_back(std::move(e));
    }
  return doc;
}

/// `path` as a URI reference's path: '%', spaces, other characters that a URI does not allow
/// and bytes beyond ASCII as %XX; '/' kept.
std::string percent_encoded(const std::string& path) {
  static const char* const HEX = "0123456789ABCDEF";
  std::string out;
  for (const char ch : path) {
    const auto c = static_cast<unsigned char>(ch);
    if (std::isalnum(c) || std::strchr("-._~/!$&'()*+,;=@", ch) != nullptr) {
      out += ch;
    } else {
      out += '%';
      out += HEX[c >> 4];
      out += HEX[c & 15];
    }
  }
  return out;
}

/// Whether the URI reference starts with a scheme ("data:", "http:", "file:"): RFC 3986's
/// letter, then letters, digits, '+', '-' or '.', then ':'.
bool has_scheme(const std::string& uri) {
  if (uri.empty() || !std::isalpha(static_cast<unsigned char>(uri[0]))) return false;
  for (std::size_t i = 1; i < uri.size(); ++i) {
    const auto c = static_cast<unsigned char>(uri[i]);
    if (c == ':') return true;
    if (!std::isalnum(c) && c != '+' && c != '-' && c != '.') return false;
  }
  return false;
}

}  // namespace

std::string relocate_image_uris(const std::string& input_json, const std::string& input_path,
                                const std::string& output_path,
                                std::vector<std::string>* warnings) {
  namespace fs = std::filesystem;
  if (input_path.empty() || same_folder(input_path, output_path)) return input_json;
  json doc = parse(input_json, "the input's");
  const auto images = doc.find("images");
  if (images == doc.end() || !images->is_array()) return input_json;
  const fs::path in_folder = fs::path(input_path).parent_path();
  const fs::path out_folder = fs::path(output_path).parent_path();
  bool changed = false;
  for (std::size_t i = 0; i < images->size(); ++i) {
    json& image = (*images)[i];
    const auto it = image.is_object() ? image.find("uri") : image.end();
    if (it == image.end() || !it->is_string()) continue;
    const std::string uri = it->get<std::string>();
    const fs::path name(percent_decoded(uri));
    if (uri.empty() || has_scheme(uri) || name.is_absolute()) continue;
    std::error_code ec;
    const fs::path file = in_folder / name;
    if (!fs::is_regular_file(file, ec)) {
      if (warnings)
        warnings->push_back(input_path + ": images[" + std::to_string(i) + "].uri '" + uri +
                            "' is no file from the glTF's folder: written as read, so it names " +
                            "no file from the output's folder either");
      continue;
    }
    const std::string moved = path_from_folder(file, out_folder);
    if (moved == name.generic_string()) continue;
    *it = percent_encoded(moved);
    changed = true;
  }
  return changed ? doc.dump(2) + "\n" : input_json;
}

std::string json_text(const std::string& bytes) {
  if (bytes.compare(0, 4, "glTF") != 0) return bytes;
  if (bytes.size() < 20 || le32(bytes, 12) > bytes.size() - 20)
    throw std::runtime_error("glTF document: the .glb has no complete JSON chunk");
  return bytes.substr(20, le32(bytes, 12));
}

std::string restore_input_json(const std::string& input_json, const std::string& written,
                               bool binary, const std::vector<int>& bounded) {
  const json in = parse(input_json, "the input's");
  if (!binary) return merged(in, parse(written, "tinygltf's"), bounded).dump(2) + "\n";
  // A .glb: the 12-byte header, the JSON chunk, then the BIN chunk as tinygltf wrote it.
  const std::string tinygltf_json = json_text(written);
  std::string text = merged(in, parse(tinygltf_json, "tinygltf's"), bounded).dump();
  while (text.size() % 4 != 0) text += ' ';  // chunks are 4-byte aligned; JSON pads with spaces
  const std::size_t rest = 20 + tinygltf_json.size();
  const std::size_t total = 20 + text.size() + (written.size() - rest);
  if (total > std::numeric_limits<std::uint32_t>::max())
    throw std::runtime_error("glTF document: the .glb would exceed 4 GiB");
  std::string glb = "glTF";
  glb.reserve(total);
  put32(glb, 2);
  put32(glb, static_cast<std::uint32_t>(total));
  put32(glb, static_cast<std::uint32_t>(text.size()));
  put32(glb, 0x4E4F534Au);  // "JSON"
  glb += text;
  glb.append(written, rest, std::string::npos);
  return glb;
}

}  // namespace shellcontract::gltf
