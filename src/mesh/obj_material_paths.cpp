// An OBJ file's `mtllib` paths, rewritten when the file is written to another folder than its
// input's (obj_material_paths.hpp). The user's .mtl files are only looked at, never copied or
// changed: the output refers to the same files where they are.
#include "mesh/obj_material_paths.hpp"

#include <algorithm>
#include <system_error>

#include "mesh/file_safety.hpp"
#include "mesh/line_tokens.hpp"

namespace shellcontract {

namespace fs = std::filesystem;

namespace {

bool has_space(const std::string& s) {
  for (const char c : s)
    if (is_line_space(c)) return true;
  return false;
}

fs::path folder_of(const std::string& path) {
  const fs::path p = fs::path(path).parent_path();
  return p.empty() ? fs::path(".") : p;
}

/// The folder with its links resolved, as far as it exists (weakly_canonical); the absolute
/// path itself if even that fails (a folder that cannot be read).
fs::path resolved_folder(const fs::path& folder) {
  std::error_code ec;
  const fs::path abs = fs::absolute(folder, ec);
  if (ec) return folder.lexically_normal();
  const fs::path c = fs::weakly_canonical(abs, ec);
  return ec ? abs.lexically_normal() : c;
}

bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::exists(p, ec) && !fs::is_directory(p, ec);
}

}  // namespace

MtllibLine mtllib_line(const std::string& bytes, std::size_t at, std::size_t end, std::size_t line) {
  while (at < end && is_line_space(bytes[at])) ++at;
  // A comment after the names ends them: a token that starts with '#'.
  for (std::size_t i = at; i < end; ++i)
    if (bytes[i] == '#' && (i == at || is_line_space(bytes[i - 1]))) {
      end = i;
      break;
    }
  while (end > at && is_line_space(bytes[end - 1])) --end;
  return MtllibLine{line, at, end};
}

std::vector<MtllibLine> find_mtllib_lines(const std::string& bytes, const std::string& text) {
  std::vector<MtllibLine> lines;
  // As ObjDocument reads lines: "\n" ends them ("\r\n" too), a lone "\r" in a file without "\n".
  const char eol = bytes.find('\n') == std::string::npos ? '\r' : '\n';
  std::size_t begin = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  for (std::size_t line = 1; begin < text.size(); ++line) {
    std::size_t end = text.find(eol, begin);
    if (end == std::string::npos) end = text.size();
    std::size_t at = begin;
    while (at < end && is_line_space(text[at])) ++at;
    if (text.compare(at, 6, "mtllib") == 0 && (at + 6 == end || is_line_space(text[at + 6])))
      lines.push_back(mtllib_line(text, at + 6, end, line));
    if (&text != &bytes)  // the line ends this statement's continuations joined
      line += static_cast<std::size_t>(
          std::count(bytes.begin() + static_cast<std::ptrdiff_t>(begin),
                     bytes.begin() + static_cast<std::ptrdiff_t>(end), eol));
    begin = end + 1;
  }
  return lines;
}

std::vector<MtllibName> mtllib_names(const std::string& bytes, const MtllibLine& line,
                                     const fs::path& obj_folder,
                                     const std::function<bool(const fs::path&)>& probe) {
  std::vector<std::pair<std::size_t, std::size_t>> tokens;
  std::size_t at = line.begin;
  for (Span t = next_token(bytes, at, line.end); t.begin != t.end; t = next_token(bytes, at, line.end))
    tokens.emplace_back(t.begin, t.end);
  std::vector<MtllibName> names;
  for (std::size_t i = 0; i < tokens.size();) {
    // Every start tried with every end made a line of many names cost the square of its names
    // in file lookups, on paths as long as the line: the runs are bounded in tokens and bytes.
    std::size_t j = i;
    bool found = false;
    for (; j < tokens.size() && j - i < kMaxMtllibNameTokens; ++j) {
      const std::size_t length = tokens[j].second - tokens[i].first;
      if (length >= kMaxMtllibNameBytes) break;  // nor does any longer run name a file
      const fs::path path = obj_folder / bytes.substr(tokens[i].first, length);
      if (probe ? probe(path) : is_file(path)) {  // an absolute name replaces the folder
        found = true;
        break;
      }
    }
    if (!found) j = i;
    MtllibName n;
    n.begin = tokens[i].first;
    n.end = tokens[j].second;
    n.name = bytes.substr(n.begin, n.end - n.begin);
    n.found = found;
    names.push_back(n);
    i = j + 1;
  }
  return names;
}

bool same_folder(const std::string& a, const std::string& b) {
  return resolved_folder(folder_of(a)) == resolved_folder(folder_of(b));
}

std::string path_from_folder(const fs::path& target, const fs::path& folder) {
  // The target's folder resolved, its own name kept: a .mtl that is a link stays that link.
  const fs::path t = resolved_folder(target.has_parent_path() ? target.parent_path() : fs::path("."));
  const fs::path full = t / target.filename();
  const fs::path rel = full.lexically_relative(resolved_folder(folder.empty() ? fs::path(".") : folder));
  return rel.empty() ? full.generic_string() : rel.generic_string();
}

std::vector<TextEdit> material_library_edits(const std::string& bytes,
                                             const std::vector<MtllibLine>& lines,
                                             const std::string& input_path,
                                             const std::string& output_path,
                                             std::vector<std::string>* warnings) {
  std::vector<TextEdit> edits;
  if (input_path.empty() || lines.empty() || same_folder(input_path, output_path)) return edits;
  const fs::path in_folder = folder_of(input_path), out_folder = folder_of(output_path);
  const auto warn = [&](const MtllibLine& l, const std::string& what) {
    if (warnings)
      warnings->push_back(printable(input_path) + ": line " + std::to_string(l.line) + ": " + what);
  };
  for (const MtllibLine& l : lines)
    for (const MtllibName& n : mtllib_names(bytes, l, in_folder)) {
      if (!n.found) {
        // A folder by that name is there to see: "not found" would send the user looking for it.
        const fs::path looked = in_folder / n.name;
        std::error_code ec;
        const std::string why =
            fs::is_directory(looked, ec)
                ? "is not a regular file ('" + printable(looked.string()) + "' is a folder)"
                : "not found (no file '" + printable(looked.string()) + "')";
        warn(l, "material library '" + printable(n.name) + "' " + why + ": written unchanged to " +
                    printable(output_path) + ", where it is looked for from that file's folder");
        continue;
      }
      if (fs::path(n.name).is_absolute()) continue;  // the same file from any folder
      const std::string moved = path_from_folder(in_folder / n.name, out_folder);
      if (moved == n.name) continue;
      if (has_space(moved) && !has_space(n.name))
        warn(l, "material library '" + printable(n.name) + "' is written to " + printable(output_path) +
                    " as '" + printable(moved) +
                    "', a path with a space: readers that split mtllib at spaces (the OBJ spec) "
                    "will not find it");
      edits.push_back(TextEdit{n.begin, n.end, moved});
    }
  return edits;
}

std::string apply_edits(const std::string& bytes, const std::vector<TextEdit>& edits) {
  std::string out;
  out.reserve(bytes.size() + bytes.size() / 4);  // new positions can be longer than read
  std::size_t at = 0;
  for (const TextEdit& e : edits) {
    out.append(bytes, at, e.begin - at);
    out += e.text;
    at = e.end;
  }
  out.append(bytes, at, std::string::npos);
  return out;
}

std::string relocate_material_libraries(const std::string& bytes, const std::string& input_path,
                                        const std::string& output_path,
                                        std::vector<std::string>* warnings) {
  // The statements with their continued lines joined, at the bytes' offsets (line_tokens.hpp):
  // the edits apply to the bytes. A continuation with no line after it (a file the OBJ readers
  // refuse) is left as it is.
  std::string joined;
  if (bytes.find('\\') != std::string::npos) {
    joined = bytes;
    join_continued_lines(joined, bytes.find('\n') == std::string::npos ? '\r' : '\n');
  }
  const std::string& text = joined.empty() ? bytes : joined;
  const std::vector<TextEdit> edits = material_library_edits(text, find_mtllib_lines(bytes, text),
                                                             input_path, output_path, warnings);
  return edits.empty() ? bytes : apply_edits(bytes, edits);
}

}  // namespace shellcontract
