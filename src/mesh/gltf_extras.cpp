// The extras of a glTF file (see file_extras.hpp, describe_gltf_extras): only the JSON is read,
// with nlohmann::json, the parser under tinygltf, so that neither the buffers (a .gltf's may be
// other files) nor tinygltf's loading are needed to name what a bare mesh leaves out.
#include <algorithm>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "core/plural.hpp"
#include "core/token_text.hpp"
#include "mesh/file_extras.hpp"
#include "mesh/gltf_json_checks.hpp"

namespace shellcontract {
namespace {

using Json = nlohmann::json;

/// The JSON text of a .glb (its first chunk) or of a .gltf (the whole file); none where it nests
/// deeper than the reader takes (gltf::MAX_JSON_DEPTH: objects_with_extras recurses), which the
/// reader has refused unless the file changed since.
std::string json_text(const std::string& bytes) {
  std::string text = bytes;
  if (bytes.compare(0, 4, "glTF") == 0) {
    if (bytes.size() < 20) return {};
    std::uint32_t length = 0;
    for (int i = 0; i < 4; ++i)
      length |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[12 + i])) << (8 * i);
    text = bytes.substr(20, std::min<std::size_t>(length, bytes.size() - 20));
  }
  if (gltf::too_deep_at(text.data(), text.size()) != std::string::npos) return {};
  return text;
}

/// A name from the file for a message: at most 24 characters, non-printable bytes as '?'.
std::string printable_name(std::string_view s) { return shorten(s, 24); }

/// " (a, b, c, ...)" of the first three names; empty without names.
std::string name_list(const std::vector<std::string>& names) {
  std::string s;
  for (std::size_t i = 0; i < names.size() && i < 3; ++i)
    s += (i ? ", " : "") + printable_name(names[i]);
  if (s.empty()) return s;
  return " (" + s + (names.size() > 3 ? ", ...)" : ")");
}

/// The array `key` of `j`; an empty one when it is missing or not an array.
const Json& array_of(const Json& j, const char* key) {
  static const Json none = Json::array();
  const auto it = j.find(key);
  return it != j.end() && it->is_array() ? *it : none;
}

/// The "name" members of the objects of `items`.
std::vector<std::string> names_of(const Json& items) {
  std::vector<std::string> out;
  for (const Json& i : items)
    if (i.is_object() && i.contains("name") && i["name"].is_string() &&
        !i["name"].get<std::string>().empty())
      out.push_back(i["name"].get<std::string>());
  return out;
}

bool has_transform(const Json& node) {
  return node.is_object() && (node.contains("matrix") || node.contains("translation") ||
                              node.contains("rotation") || node.contains("scale"));
}

/// How many objects under `j` (itself included) carry application data ("extras").
std::size_t objects_with_extras(const Json& j) {
  std::size_t n = j.is_object() && j.contains("extras");
  if (j.is_structured())
    for (const Json& child : j) n += objects_with_extras(child);
  return n;
}

}  // namespace

FileExtras describe_gltf_extras(const std::string& bytes) {
  FileExtras e;
  const Json j = Json::parse(json_text(bytes), nullptr, false);
  if (!j.is_object()) return e;
  std::size_t primitives = 0, morphed = 0;
  std::set<std::string> attributes;
  for (const Json& mesh : array_of(j, "meshes"))
    for (const Json& p : array_of(mesh, "primitives")) {
      if (!p.is_object()) continue;
      ++primitives;
      morphed += !array_of(p, "targets").empty();
      if (p.contains("attributes") && p["attributes"].is_object())
        for (const auto& a : p["attributes"].items())
          if (a.key() != "POSITION") attributes.insert(printable_name(a.key()));
    }
  if (!attributes.empty()) {
    std::string s;
    for (const std::string& a : attributes) s += (s.empty() ? "" : ", ") + a;
    e.items.push_back("vertex attributes " + s);
  }
  if (morphed)
    e.items.push_back("morph targets (on " + counted(morphed, "primitive)", "primitives)"));
  if (primitives > 1)
    e.items.push_back(std::to_string(primitives) + " primitives (written as one)");
  const Json& nodes = array_of(j, "nodes");
  const bool transforms = std::any_of(nodes.begin(), nodes.end(), has_transform);
  if (nodes.size() > 1 || transforms)
    e.items.push_back(
        counted(nodes.size(), "node", "nodes") +
        (transforms ? one_or_many(nodes.size(), " and its transform", " and their transforms") +
                          std::string(" (applied to the positions)")
                    : std::string()));
  std::vector<std::string> names = names_of(nodes);
  for (const std::string& n : names_of(array_of(j, "meshes"))) names.push_back(n);
  if (!names.empty()) e.items.push_back("node and mesh names" + name_list(names));
  const std::size_t scenes = array_of(j, "scenes").size();
  if (scenes > 1)
    e.items.push_back(counted(scenes, "scene", "scenes") + " (the default scene's meshes written)");
  const Json& materials = array_of(j, "materials");
  if (!materials.empty())
    e.items.push_back(counted(materials.size(), "material", "materials") +
                      name_list(names_of(materials)));
  if (const std::size_t n = array_of(j, "textures").size())
    e.items.push_back(counted(n, "texture", "textures"));
  if (const std::size_t n = array_of(j, "images").size())
    e.items.push_back(counted(n, "image", "images"));
  if (const std::size_t n = array_of(j, "animations").size())
    e.items.push_back(counted(n, "animation", "animations"));
  if (const std::size_t n = array_of(j, "skins").size())
    e.items.push_back(counted(n, "skin", "skins"));
  if (const std::size_t n = array_of(j, "cameras").size())
    e.items.push_back(counted(n, "camera", "cameras"));
  std::vector<std::string> extensions;
  for (const Json& x : array_of(j, "extensionsUsed"))
    if (x.is_string()) extensions.push_back(x.get<std::string>());
  if (!extensions.empty()) e.items.push_back("extensions" + name_list(extensions));
  if (const std::size_t n = objects_with_extras(j))
    e.items.push_back("application data (extras) on " + counted(n, "object", "objects"));
  return e;
}

std::vector<std::string> gltf_file_uris(const std::string& bytes) {
  std::vector<std::string> out;
  std::set<std::string> seen;  // a file named by many images or buffers: once, in linear time
  const Json j = Json::parse(json_text(bytes), nullptr, false);
  if (!j.is_object()) return out;
  for (const char* key : {"buffers", "images"})
    for (const Json& item : array_of(j, key))
      if (item.is_object() && item.contains("uri") && item["uri"].is_string()) {
        const std::string uri = item["uri"].get<std::string>();
        if (uri.rfind("data:", 0) != 0 && seen.insert(uri).second) out.push_back(uri);
      }
  return out;
}

}  // namespace shellcontract
