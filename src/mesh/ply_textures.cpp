#include "mesh/ply_textures.hpp"

#include <filesystem>

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

}  // namespace shellcontract::ply
