#include "mesh/ply_textures.hpp"

#include <filesystem>
#include <string_view>

namespace shellcontract::ply {
namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f' || c == '\r'; }

std::string trimmed(const std::string& s) {
  std::size_t b = 0, e = s.size();
  while (b < e && is_blank(s[b])) ++b;
  while (e > b && is_blank(s[e - 1])) --e;
  return s.substr(b, e - b);
}

}  // namespace

FaceMaterials texture_materials(const std::string& ply_path, const std::vector<Comment>& comments) {
  namespace fs = std::filesystem;
  static const std::string KEY = "TextureFile";
  FaceMaterials m;
  const fs::path folder = fs::path(ply_path).parent_path();
  for (const Comment& c : comments) {
    const std::string text = trimmed(c.text);
    if (text.compare(0, KEY.size(), KEY) != 0) continue;
    if (text.size() > KEY.size() && !is_blank(text[KEY.size()])) continue;  // TextureFiles, ...
    const std::string file = trimmed(text.substr(KEY.size()));
    const fs::path p(file);
    m.names.push_back(file);
    m.textures.push_back({file.empty() || p.is_absolute() ? file : (folder / p).string(), c.line});
  }
  if (!m.names.empty()) m.source = ply_path;
  return m;
}

std::vector<TextEdit> texture_file_edits(const std::string& bytes, const std::string& input_path,
                                         const std::string& output_path,
                                         std::vector<std::string>* warnings) {
  namespace fs = std::filesystem;
  std::vector<TextEdit> edits;
  if (input_path.empty() || same_folder(input_path, output_path)) return edits;
  const fs::path in_folder = fs::path(input_path).parent_path();
  const fs::path out_folder = fs::path(output_path).parent_path();
  static const std::string COMMENT = "comment", KEY = "TextureFile";
  std::size_t line = 0;
  for (std::size_t at = 0; at < bytes.size();) {
    const std::size_t nl = bytes.find('\n', at);
    const std::size_t end = nl == std::string::npos ? bytes.size() : nl;
    ++line;
    // The line without its '\r' and the blanks around its text.
    std::size_t b = at, e = end;
    while (b < e && is_blank(bytes[b])) ++b;
    while (e > b && is_blank(bytes[e - 1])) --e;
    const std::string_view text(bytes.data() + b, e - b);
    if (text == "end_header") break;
    at = end + 1;
    if (text.substr(0, COMMENT.size()) != COMMENT || text.size() <= COMMENT.size() ||
        !is_blank(text[COMMENT.size()]))
      continue;
    std::size_t k = b + COMMENT.size();
    while (k < e && is_blank(bytes[k])) ++k;
    if (bytes.compare(k, KEY.size(), KEY) != 0 || k + KEY.size() >= e ||
        !is_blank(bytes[k + KEY.size()]))
      continue;
    k += KEY.size();
    while (k < e && is_blank(bytes[k])) ++k;
    const std::string name = bytes.substr(k, e - k);
    if (name.empty() || fs::path(name).is_absolute()) continue;
    std::error_code ec;
    const fs::path image = in_folder / name;
    if (!fs::is_regular_file(image, ec)) {
      if (warnings)
        warnings->push_back(input_path + ": line " + std::to_string(line) + ": TextureFile '" +
                            name + "' is no file from the PLY's folder: written as read, so " +
                            "it names no file from the output's folder either");
      continue;
    }
    const std::string moved = path_from_folder(image, out_folder);
    if (moved != name) edits.push_back({k, e, moved});
  }
  return edits;
}

}  // namespace shellcontract::ply
