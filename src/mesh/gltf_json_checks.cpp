// Checks of a glTF's JSON before tinygltf parses it (gltf_json_checks.hpp).
#include "mesh/gltf_json_checks.hpp"

#include <algorithm>
#include <limits>
#include <nlohmann/json.hpp>

#include "mesh/file_safety.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract::gltf {
namespace {

using json = nlohmann::json;

[[noreturn]] void fail(const std::string& path, const std::string& problem,
                       const std::string& details) {
  throw InputError(path + ": " + problem + ": " + details);
}

/// A JSON value for a message: its JSON text, cut short.
std::string shown(const json& j) {
  std::string s = j.dump(-1, ' ', true, json::error_handler_t::replace);
  return s.size() > 40 ? s.substr(0, 40) + "..." : s;
}

/// `uri` decoded as tinygltf decodes a buffer's URI before it looks for the file (its
/// dlib::urldecode: "%XX" a byte, '+' a space).
std::string decoded(const std::string& uri) {
  const auto hex = [](char c) {
    return c >= '0' && c <= '9'   ? c - '0'
           : c >= 'a' && c <= 'f' ? c - 'a' + 10
           : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                  : 0;
  };
  std::string s;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '+') {
      s += ' ';
    } else if (uri[i] == '%' && i + 2 < uri.size()) {
      s += static_cast<char>(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
      i += 2;
    } else {
      s += uri[i];
    }
  }
  return s;
}

/// `text` cut at each `at`.
std::vector<std::string> split(const std::string& text, char at) {
  std::vector<std::string> out(1);
  for (const char c : text)
    if (c == at)
      out.emplace_back();
    else
      out.back() += c;
  return out;
}

/// The members that hold an index into one of the file's arrays (the spec's glTFid, and a
/// texture's texCoord, the n of its TEXCOORD_n), as paths: "*" an element of an array, "?" any
/// member. tinygltf keeps each as an int, cutting a larger JSON integer to its low 32 bits (node
/// "mesh": 4294967296 draws mesh 0); a member of "extras" or of an extension is not read as one.
/// The default "scene" is checked with the top level.
const std::vector<std::vector<std::string>>& index_members() {
  static const std::vector<std::vector<std::string>> paths = [] {
    const char* const list =
        "scenes/*/nodes/* nodes/*/camera nodes/*/children/* nodes/*/skin nodes/*/mesh "
        "meshes/*/primitives/*/attributes/? meshes/*/primitives/*/indices "
        "meshes/*/primitives/*/material meshes/*/primitives/*/targets/*/? "
        "accessors/*/bufferView accessors/*/sparse/indices/bufferView "
        "accessors/*/sparse/values/bufferView bufferViews/*/buffer images/*/bufferView "
        "textures/*/sampler textures/*/source skins/*/inverseBindMatrices skins/*/skeleton "
        "skins/*/joints/* animations/*/channels/*/sampler animations/*/channels/*/target/node "
        "animations/*/samplers/*/input animations/*/samplers/*/output";
    std::vector<std::vector<std::string>> out;
    for (const std::string& p : split(list, ' ')) out.push_back(split(p, '/'));
    for (const char* texture :
         {"normalTexture", "occlusionTexture", "emissiveTexture",
          "pbrMetallicRoughness/baseColorTexture", "pbrMetallicRoughness/metallicRoughnessTexture"})
      for (const char* member : {"index", "texCoord"})
        out.push_back(split(std::string("materials/*/") + texture + "/" + member, '/'));
    return out;
  }();
  return paths;
}

/// Where the parser is, one level per open array or object, to name the member a value is in:
/// its callback tells each event's level, but not always the end of an array or object (never
/// that of one being dropped), so a level's state is set when its array or object starts.
class JsonPlace {
 public:
  /// The parser's callback, for every event in order: follows the levels and refuses an integer
  /// in an index member that is negative or more than the largest int.
  void on_event(int depth, json::parse_event_t event, const json& parsed, const std::string& path) {
    const auto d = static_cast<std::size_t>(depth);
    if (event == json::parse_event_t::key) {
      if (d < levels_.size()) levels_[d].key = parsed.get<std::string>();
      return;
    }
    const bool starts =
        event == json::parse_event_t::object_start || event == json::parse_event_t::array_start;
    if (!starts && event != json::parse_event_t::value) return;
    if (d < levels_.size() && levels_[d].array) levels_[d].key = std::to_string(levels_[d].next++);
    if (starts) {
      levels_.resize(d + 2);
      levels_[d + 1] = Level{event == json::parse_event_t::array_start, 0, {}};
      return;
    }
    if (!parsed.is_number_integer()) return;  // unsigned or signed
    const bool negative = !parsed.is_number_unsigned() && parsed.get<std::int64_t>() < 0;
    if (!negative &&
        parsed.get<std::uint64_t>() <= static_cast<std::uint64_t>(std::numeric_limits<int>::max()))
      return;
    if (!is_index(d)) return;
    fail(path, "bad index",
         name(d) + " is " + parsed.dump() +
             (negative ? ", not an index (an index is 0 or more)"
                       : ", more than the largest index that is read (" +
                             std::to_string(std::numeric_limits<int>::max()) + ")"));
  }

 private:
  struct Level {
    bool array = false;
    std::size_t next = 0;  ///< an array's next element
    std::string key;       ///< the member (or the element's number) being read
  };
  /// Whether the value being read at level `d` (levels 1 to d) is in an index member.
  bool is_index(std::size_t d) const {
    for (const std::vector<std::string>& p : index_members()) {
      if (p.size() != d) continue;
      bool same = true;
      for (std::size_t i = 0; i < d && same; ++i) {
        const Level& l = levels_[i + 1];
        same = p[i] == "?" ? !l.array : p[i] == "*" ? l.array : !l.array && p[i] == l.key;
      }
      if (same) return true;
    }
    return false;
  }
  /// The member as a path: "meshes[0].primitives[1].attributes.POSITION".
  std::string name(std::size_t d) const {
    std::string s;
    for (std::size_t i = 1; i <= d; ++i)
      s += levels_[i].array ? "[" + levels_[i].key + "]"
                            : (i > 1 ? "." : "") + printable(levels_[i].key, 40);
    return s;
  }
  std::vector<Level> levels_{Level{}};  ///< level 0: outside the top-level value
};

}  // namespace

std::size_t too_deep_at(const char* text, std::size_t size) {
  std::size_t depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < size; ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;  // the escaped character, a quote or a backslash, does not end the string
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > MAX_JSON_DEPTH) return i;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return std::string::npos;
}

std::vector<DeclaredBuffer> check_top_level(const std::string& path, const char* text,
                                            std::size_t size, std::size_t first_byte) {
  const std::size_t deep = too_deep_at(text, size);
  if (deep != std::string::npos)
    fail(path, "JSON nested too deeply",
         "the JSON nests deeper than " + std::to_string(MAX_JSON_DEPTH) + " levels (byte " +
             std::to_string(first_byte + deep) + " opens level " +
             std::to_string(MAX_JSON_DEPTH + 1) + ")");
  // Only the members checked here are kept: the rest (a .gltf's data URIs) is parsed and dropped,
  // its index members checked on the way (one pass).
  JsonPlace place;
  const json top = json::parse(
      text, text + size,
      [&](int depth, json::parse_event_t event, json& parsed) {
        place.on_event(depth, event, parsed, path);
        return depth != 1 || event != json::parse_event_t::key || parsed == "asset" ||
               parsed == "scene" || parsed == "buffers";
      },
      false);
  std::vector<DeclaredBuffer> buffers;
  if (!top.is_object()) return buffers;  // tinygltf says what is wrong
  const auto asset = top.find("asset");
  if (asset != top.end() && asset->is_object()) {
    const auto version = asset->find("version");
    if (version != asset->end() && version->is_string()) {
      const std::string v = version->get<std::string>();
      if (v.substr(0, v.find('.')) != "2")
        fail(path, "unsupported glTF version",
             "asset.version is " + shown(*version) + " (only glTF 2.x is read)");
    }
    const auto min_version = asset->find("minVersion");
    if (min_version != asset->end() && min_version->is_string() &&
        min_version->get<std::string>() != "2.0")
      fail(path, "unsupported glTF version",
           "asset.minVersion is " + shown(*min_version) +
               ": the file needs a reader of a later glTF than 2.0");
  }
  const auto scene = top.find("scene");
  if (scene != top.end()) {
    // tinygltf takes a negative or fractional "scene" as none (scene 0) and cuts a large one
    // to an int.
    if (!scene->is_number_unsigned())
      fail(path, "bad default scene", "\"scene\" is " + shown(*scene) + ", not a scene index");
    if (scene->get<std::uint64_t>() > static_cast<std::uint64_t>(std::numeric_limits<int>::max()))
      fail(path, "scene out of range", "the default scene is " + shown(*scene));
  }
  const auto list = top.find("buffers");
  if (list != top.end() && list->is_array())
    for (const json& b : *list) {
      DeclaredBuffer d;
      if (b.is_object()) {
        const auto uri = b.find("uri"), length = b.find("byteLength");
        if (uri != b.end() && uri->is_string()) d.uri = uri->get<std::string>();
        d.file = decoded(d.uri);
        if (length != b.end() && length->is_number_unsigned())
          d.byte_length = length->get<std::uint64_t>();
      }
      buffers.push_back(std::move(d));
    }
  return buffers;
}

std::vector<std::size_t> buffers_naming(const std::vector<DeclaredBuffer>& declared,
                                        const std::string& file) {
  const auto names = [&](const std::string& uri) {
    return !uri.empty() && uri.size() <= file.size() &&
           file.compare(file.size() - uri.size(), uri.size(), uri) == 0;
  };
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < declared.size(); ++i) {
    const DeclaredBuffer& b = declared[i];
    if (b.uri.rfind("data:", 0) != 0 && (names(b.uri) || names(b.file))) out.push_back(i);
  }
  return out;
}

/// The bytes: the byteLength of the buffer whose URI names the file (tinygltf refuses a file of
/// another size once it has read it: a larger one is refused before), or where no URI is seen to
/// name it (tinygltf decodes a URI by rules of its own), the largest byteLength declared; never
/// more than the 4 GiB a glTF file may have (load_model), whatever byteLength says, so that a
/// file of any size costs no more than that.
std::pair<std::uint64_t, std::string> buffer_file_bound(const std::vector<DeclaredBuffer>& declared,
                                                        const std::string& file) {
  std::uint64_t largest = 0, named = 0;
  for (const DeclaredBuffer& b : declared) largest = std::max(largest, b.byte_length);
  std::size_t which = declared.size();
  for (const std::size_t i : buffers_naming(declared, file))
    if (which == declared.size() || declared[i].byte_length > named)
      which = i, named = declared[i].byte_length;
  const std::uint64_t LIMIT = std::numeric_limits<std::uint32_t>::max();
  if (which == declared.size())
    return {std::min(largest, LIMIT),
            std::to_string(largest) + ", the largest byteLength of the file's buffers"};
  const std::string buffer = "buffer " + std::to_string(which);
  if (named > LIMIT)
    return {LIMIT, std::to_string(LIMIT) + ", the most a buffer is read with (4 GiB, as a file; " +
                       buffer + "'s byteLength is " + std::to_string(named) + ")"};
  return {named, buffer + "'s byteLength of " + std::to_string(named) + " ('" +
                     printable(declared[which].uri, 80) + "')"};
}

}  // namespace shellcontract::gltf
