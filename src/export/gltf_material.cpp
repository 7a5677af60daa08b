#include "export/gltf_material.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <system_error>

#include "core/decimal_text.hpp"
#include "export/gltf_input_materials.hpp"
#include "mesh/file_key.hpp"
#include "mesh/file_safety.hpp"
#include "mesh/line_tokens.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

/// A material library is a short text of definitions; the bound keeps a wrong file from
/// filling the memory.
constexpr std::uint64_t MAX_MTL_BYTES = std::uint64_t{64} << 20;
/// A .glb's chunk lengths are 32-bit: an image past a quarter of that leaves the frames too little.
constexpr std::uint64_t MAX_TEXTURE_BYTES = std::uint64_t{1} << 30;

std::vector<std::string> tokens(const std::string& s) {
  std::vector<std::string> out;
  std::size_t at = 0;
  for (Span t = next_token(s, at, s.size()); t.begin != t.end; t = next_token(s, at, s.size()))
    out.push_back(s.substr(t.begin, t.end - t.begin));
  return out;
}

std::string trimmed(const std::string& s) {
  std::size_t b = 0, e = s.size();
  while (b < e && is_line_space(s[b])) ++b;
  while (e > b && is_line_space(s[e - 1])) --e;
  return s.substr(b, e - b);
}

/// The whole token as a finite double, or nothing.
std::optional<double> number(const std::string& t) {
  double v = 0.0;
  if (!parse_c_number(t, v) || !std::isfinite(v)) return std::nullopt;
  return v;
}

/// The file name of a map_Kd line's arguments: its options (-o u v w, -clamp on, ...) skipped;
/// the rest of the line, spaces included (names with spaces exist). `placement`: the options
/// that place the texture otherwise than the glTF does (scale 1, offset 0, repeating), as given
/// ("-s 2 2 1, -clamp on"), which the .glb does not carry; empty when there are none.
std::string map_file_name(const std::string& args, std::string& placement) {
  // The options and how many arguments each takes; -o, -s and -t take one to three numbers.
  static const std::map<std::string, int> fixed = {
      {"-blendu", 1}, {"-blendv", 1}, {"-bm", 1}, {"-boost", 1}, {"-cc", 1}, {"-clamp", 1},
      {"-imfchan", 1}, {"-mm", 2}, {"-texres", 1}, {"-type", 1}};
  std::size_t at = 0;
  auto next = [&](bool consume) {
    std::size_t after = at;
    const Span t = next_token(args, after, args.size());
    if (consume) at = after;
    return args.substr(t.begin, t.end - t.begin);
  };
  const auto note = [&](const std::string& given) {
    placement += (placement.empty() ? "" : ", ") + given;
  };
  for (std::string t = next(false); !t.empty() && t[0] == '-'; t = next(false)) {
    next(true);
    const auto f = fixed.find(t);
    if (f != fixed.end()) {
      std::string values;
      for (int k = 0; k < f->second; ++k) values += " " + next(true);
      if (t == "-clamp" && values == " on") note(t + values);
    } else if (t == "-o" || t == "-s" || t == "-t") {
      // Each number against the option's default (scale 1, offset and turbulence 0).
      const double identity = t == "-s" ? 1.0 : 0.0;
      std::string values;
      bool moves = false;
      for (int k = 0; k < 3 && number(next(false)); ++k) {
        const std::string v = next(true);
        values += " " + v;
        moves = moves || *number(v) != identity;
      }
      if (moves) note(t + values);
    }
    // An unknown option: only the option itself is skipped.
  }
  return trimmed(args.substr(at));
}

/// A file's bytes, or the reason it cannot be had: read_regular_file's refusals (a folder, a
/// device such as /dev/zero, a FIFO that would block or never end, a file beyond `max_bytes`) as
/// well as a read error, so that a material never stalls or fills the memory of the run.
std::optional<std::string> read_bytes(const std::string& path, std::uint64_t max_bytes, std::string& why) {
  try {
    return read_regular_file(path, max_bytes);
  } catch (const InputError& e) {
    why = e.what();
    return std::nullopt;
  }
}

}  // namespace

std::vector<MtlMaterial> parse_mtl(const std::string& name, const std::string& bytes,
                                   std::vector<std::string>& warnings) {
  std::vector<MtlMaterial> out;
  const fs::path folder = fs::path(name).parent_path();
  auto warn = [&](std::size_t line, const std::string& what) {
    warnings.push_back(name + ": line " + std::to_string(line) + ": " + what);
  };
  std::istringstream in(bytes);
  std::string text;
  bool has_d = false;
  for (std::size_t line = 1; std::getline(in, text); ++line) {
    const std::size_t hash = text.find('#');
    if (hash != std::string::npos) text.resize(hash);
    std::size_t at = 0;
    while (at < text.size() && is_line_space(text[at])) ++at;
    std::size_t key_end = at;
    while (key_end < text.size() && !is_line_space(text[key_end])) ++key_end;
    const std::string key = text.substr(at, key_end - at);
    const std::string rest = text.substr(key_end);
    if (key == "newmtl") {
      out.emplace_back();
      out.back().name = trimmed(rest);
      out.back().file = name;
      has_d = false;
      // Kept, so that the lines after it do not change the material before; but a bare usemtl
      // means no material, so nothing can use this one.
      if (out.back().name.empty())
        warn(line, "newmtl without a name: no usemtl can name its material");
      continue;
    }
    if (key != "Kd" && key != "d" && key != "Tr" && key != "map_Kd") continue;
    if (out.empty()) {
      warn(line, key + " before any newmtl: ignored");
      continue;
    }
    MtlMaterial& m = out.back();
    const std::vector<std::string> t = tokens(rest);
    if (key == "Kd") {
      if (!t.empty() && (t[0] == "spectral" || t[0] == "xyz")) {
        warn(line, "Kd " + t[0] + " is not supported: Kd left at white");
        continue;
      }
      // One number means the same for red, green and blue (the MTL spec).
      std::array<double, 3> kd{};
      bool good = t.size() == 1 || t.size() == 3;
      for (std::size_t k = 0; good && k < 3; ++k) {
        const auto v = number(t[t.size() == 1 ? 0 : k]);
        good = v.has_value() && *v >= 0.0;
        if (good) kd[k] = std::min(*v, 1.0);  // glTF's base colour ends at 1
      }
      if (good)
        m.kd = kd;
      else
        warn(line, "Kd '" + trimmed(rest) + "' is not three non-negative numbers: ignored");
    } else if (key == "d" || key == "Tr") {
      std::size_t i = 0;
      if (key == "d" && t.size() == 2 && t[0] == "-halo") i = 1;  // the halo form: its factor
      const auto v = t.size() == i + 1 ? number(t[i]) : std::nullopt;
      if (!v || *v < 0.0 || *v > 1.0) {
        warn(line, key + " '" + trimmed(rest) + "' is not a number in [0, 1]: ignored");
      } else if (key == "d") {
        m.alpha = *v;
        has_d = true;
      } else if (!has_d) {
        m.alpha = 1.0 - *v;
      }
    } else {  // map_Kd
      std::string placement;
      const std::string file = map_file_name(rest, placement);
      if (file.empty()) {
        warn(line, "map_Kd without a file name: ignored");
        continue;
      }
      // The OBJ keeps its .mtl as it is; only the .glb places the texture otherwise.
      if (!placement.empty())
        warn(line, "map_Kd " + placement +
                       ": not carried into the glTF, whose texture is placed at scale 1, offset "
                       "0, repeating");
      const fs::path p(file);
      m.texture = p.is_absolute() ? file : (folder / p).string();
      m.texture_line = line;
    }
  }
  return out;
}

std::vector<MtlTextureFile> mtl_texture_files(const std::string& path) {
  std::vector<MtlTextureFile> out;
  std::string why;
  const std::optional<std::string> bytes = read_bytes(path, MAX_MTL_BYTES, why);
  if (!bytes) return out;
  const fs::path folder = fs::path(path).parent_path();
  std::istringstream in(*bytes);
  std::string text;
  for (std::size_t line = 1; std::getline(in, text); ++line) {
    const std::size_t hash = text.find('#');  // as parse_mtl reads a line
    if (hash != std::string::npos) text.resize(hash);
    std::size_t at = 0;
    const Span k = next_token(text, at, text.size());
    std::string key = text.substr(k.begin, k.end - k.begin), lower = key;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    // map_aat is a switch ("on"), not a file.
    const bool texture = (lower.rfind("map_", 0) == 0 && lower != "map_aat") || lower == "bump" ||
                         lower == "disp" || lower == "decal" || lower == "refl" || lower == "norm";
    if (!texture) continue;
    std::string placement;  // the texture's file only, here
    const std::string file = map_file_name(text.substr(k.end), placement);
    if (file.empty()) continue;
    const fs::path p(file);
    out.push_back({p.is_absolute() ? file : (folder / p).string(), key, line});
  }
  return out;
}

std::string image_mime_type(const std::vector<unsigned char>& b) {
  static const unsigned char png[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (b.size() >= 8 && std::equal(png, png + 8, b.begin())) return "image/png";
  if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return "image/jpeg";
  return {};
}

namespace {

/// A texture file as read for a material: its bytes and type, or why it has none. The materials
/// that name one file share it (by file_key: any spelling of the file), so that it is read and
/// held once however many name it.
struct TextureRead {
  enum class Outcome { missing, unreadable, not_an_image, image } outcome = Outcome::missing;
  std::string why;  ///< read_regular_file's refusal (unreadable)
  ImageBytes image;
  std::string mime_type;
};
using TextureReads = std::map<std::string, TextureRead>;

const TextureRead& read_texture(const std::string& path, TextureReads& reads) {
  const auto [at, added] = reads.try_emplace(file_key(path));
  TextureRead& t = at->second;
  if (!added) return t;
  std::error_code ec;
  if (!fs::exists(path, ec)) return t;
  const std::optional<std::string> read = read_bytes(path, MAX_TEXTURE_BYTES, t.why);
  if (!read) {
    t.outcome = TextureRead::Outcome::unreadable;
    return t;
  }
  std::vector<unsigned char> bytes(read->begin(), read->end());
  t.mime_type = image_mime_type(bytes);
  if (t.mime_type.empty()) {
    t.outcome = TextureRead::Outcome::not_an_image;
    return t;
  }
  t.outcome = TextureRead::Outcome::image;
  t.image = std::move(bytes);
  return t;
}

/// The glTF material of `m`, its texture embedded when it can be (else a warning, and none).
/// @param reads the texture files read so far, which the materials share
/// @param key what the warnings call the line that names the texture ("map_Kd", "TextureFile")
GltfMaterial to_gltf(const MtlMaterial& m, bool has_texcoords, TextureReads& reads,
                     std::vector<std::string>& warnings, const std::string& key = "map_Kd") {
  GltfMaterial g;
  g.name = m.name;
  g.base_colour = {m.kd[0], m.kd[1], m.kd[2], m.alpha};
  if (m.texture.empty()) return g;
  const std::string where = m.file + ": line " + std::to_string(m.texture_line) + ": ";
  if (!has_texcoords) {
    warnings.push_back(where + key + " '" + m.texture +
                       "' not embedded: the mesh has no texture coordinates on every face");
    return g;
  }
  const TextureRead& t = read_texture(m.texture, reads);
  switch (t.outcome) {
    case TextureRead::Outcome::missing:
      warnings.push_back(where + key + " '" + m.texture +
                         "' not found: the glTF's material has no texture");
      break;
    case TextureRead::Outcome::unreadable:
      warnings.push_back(where + key + " '" + m.texture + "' cannot be read (" + t.why +
                         "): the glTF's material has no texture");
      break;
    case TextureRead::Outcome::not_an_image:
      warnings.push_back(
          where + key + " '" + m.texture +
          "' is neither PNG nor JPEG (glTF's image types): the glTF's material has no texture");
      break;
    case TextureRead::Outcome::image:
      g.image = t.image;
      g.image_mime_type = t.mime_type;
      break;
  }
  return g;
}

/// The materials of a PLY's texture files (FaceMaterials::textures): each one a face uses, in
/// header order, white with its image. A face whose texnumber names no texture file has no
/// material (one warning counts them).
GltfFaceMaterials texture_file_materials(const FaceMaterials& materials,
                                         const std::vector<bool>& used, bool has_texcoords,
                                         std::vector<std::string>& warnings) {
  GltfFaceMaterials out;
  TextureReads reads;
  std::size_t unnamed = 0;
  for (const int m : materials.face_material)
    if (m < 0 || static_cast<std::size_t>(m) >= materials.names.size()) ++unnamed;
  if (unnamed > 0)
    warnings.push_back(materials.source + ": " + std::to_string(unnamed) + " of " +
                       std::to_string(materials.face_material.size()) +
                       " faces have a texnumber that names none of the " +
                       std::to_string(materials.textures.size()) +
                       " TextureFile comments: they have no material in the glTF");
  std::vector<int> index(materials.names.size(), -1);
  for (std::size_t i = 0; i < materials.names.size() && i < materials.textures.size(); ++i) {
    if (!used[i]) continue;
    const FaceMaterials::Texture& t = materials.textures[i];
    MtlMaterial m;
    m.name = materials.names[i];
    m.texture = t.path;
    m.texture_line = t.line;
    m.file = materials.source;
    if (t.path.empty())
      warnings.push_back(materials.source + ": line " + std::to_string(t.line) +
                         ": TextureFile without a file name: the glTF's material has no texture");
    index[i] = static_cast<int>(out.materials.size());
    out.materials.push_back(to_gltf(m, has_texcoords, reads, warnings, "TextureFile"));
  }
  if (out.materials.empty()) return out;
  for (const int m : materials.face_material)
    out.face_material.push_back(m >= 0 && static_cast<std::size_t>(m) < index.size()
                                    ? index[static_cast<std::size_t>(m)]
                                    : -1);
  return out;
}

}  // namespace

GltfFaceMaterials gltf_materials(const FaceMaterials& materials, bool has_texcoords,
                                 std::vector<std::string>& warnings) {
  if (materials.gltf) return gltf::gltf_input_materials(materials, has_texcoords, warnings);
  GltfFaceMaterials out;
  std::vector<bool> used(materials.names.size(), false);
  for (const int m : materials.face_material)
    if (m >= 0 && static_cast<std::size_t>(m) < used.size()) used[static_cast<std::size_t>(m)] = true;
  if (!materials.textures.empty())
    return texture_file_materials(materials, used, has_texcoords, warnings);
  if (std::find(used.begin(), used.end(), true) == used.end()) return out;

  // Every library is read (and warns) even when an earlier one defines every material: the
  // first definition wins, in the order the OBJ names them. A library named again (by any
  // spelling of the file) is read once, where it is first named: read again it could only
  // repeat its warnings and define nothing new.
  std::vector<std::optional<MtlMaterial>> found(materials.names.size());
  std::set<std::string> read_libraries;
  for (const FaceMaterials::Library& lib : materials.libraries) {
    if (!read_libraries.insert(file_key(lib.path)).second) continue;
    if (!lib.found) {
      // The document finds no file by that name; a folder by that name is there to see, so
      // "not found" would send the user looking for it.
      std::error_code ec;
      const std::string why =
          fs::is_directory(lib.path, ec) ? "is not a regular file (it is a folder)" : "not found";
      warnings.push_back(materials.source + ": line " + std::to_string(lib.line) +
                         ": material library '" + lib.path + "' " + why +
                         ": the glTF has no material from it");
      continue;
    }
    std::string why;
    const std::optional<std::string> bytes = read_bytes(lib.path, MAX_MTL_BYTES, why);
    if (!bytes) {
      warnings.push_back(materials.source + ": line " + std::to_string(lib.line) +
                         ": material library '" + lib.path + "' cannot be read (" + why + ")");
      continue;
    }
    for (MtlMaterial& m : parse_mtl(lib.path, *bytes, warnings))
      for (std::size_t i = 0; i < materials.names.size(); ++i)
        if (used[i] && !found[i] && m.name == materials.names[i]) found[i] = m;
  }

  // glTF materials in the order of first use; a face of an undefined one gets none.
  TextureReads reads;
  std::vector<int> index(materials.names.size(), -1);
  for (std::size_t i = 0; i < materials.names.size(); ++i) {
    if (!used[i]) continue;
    if (!found[i]) {
      warnings.push_back(materials.source + ": material '" + materials.names[i] +
                         "' is defined in none of its material libraries: its faces have no "
                         "material in the glTF");
      continue;
    }
    index[i] = static_cast<int>(out.materials.size());
    out.materials.push_back(to_gltf(*found[i], has_texcoords, reads, warnings));
  }
  if (out.materials.empty()) return out;
  out.face_material.reserve(materials.face_material.size());
  for (const int m : materials.face_material)
    out.face_material.push_back(m >= 0 && static_cast<std::size_t>(m) < index.size()
                                    ? index[static_cast<std::size_t>(m)]
                                    : -1);
  return out;
}

}  // namespace shellcontract
