// The material libraries an OBJ file names (`mtllib`), and the same lines rewritten for a copy
// of the file in another folder (docs/design/attributes.md, "Material libraries"). A relative
// mtllib path is relative to the OBJ file's folder, so an OBJ written elsewhere with its input's
// lines verbatim loses its materials (and its textures) without a word from any reader.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace shellcontract {

/// One `mtllib` line: the byte span of its file names (after the keyword, without the line's
/// trailing spaces and a comment at its end).
struct MtllibLine {
  std::size_t line = 0;  ///< 1-based
  std::size_t begin = 0, end = 0;
};

/// The file names of an mtllib line, as spans of the file's bytes.
struct MtllibName {
  std::size_t begin = 0, end = 0;
  std::string name;  ///< the text of [begin, end)
  bool found = false;  ///< the name is an existing file from the OBJ's folder
};

/// The span of an mtllib line's names: [at, end) is the line after its keyword.
MtllibLine mtllib_line(const std::string& bytes, std::size_t at, std::size_t end, std::size_t line);

/// Every mtllib line of an OBJ file's bytes, with the document's line rules (obj_document.cpp):
/// `text` is `bytes` with their continued lines joined (join_continued_lines), or `bytes` itself
/// when none is; a line is the one its statement starts on.
std::vector<MtllibLine> find_mtllib_lines(const std::string& bytes, const std::string& text);

/// The most tokens one mtllib name is joined from (a file name with that many spaces).
inline constexpr std::size_t kMaxMtllibNameTokens = 64;
/// A run of tokens this long or longer names no file: Linux's PATH_MAX (the path with its
/// terminating zero), which no longer run can be under either.
inline constexpr std::size_t kMaxMtllibNameBytes = 4096;

/// The names of one mtllib line. The OBJ spec separates several names with spaces; a name with
/// spaces in it (Blender's exporter writes the .mtl's file name as it is, and its importer reads
/// the rest of the line as one name) is taken whole when the text with its spaces names an
/// existing file from `obj_folder`: from each token, the shortest run of tokens (at most
/// kMaxMtllibNameTokens, shorter than kMaxMtllibNameBytes) that names an existing file is one
/// name; a token that starts no such run is a name of its own (not found). So a line of n names
/// costs at most n * kMaxMtllibNameTokens file lookups.
/// @param probe whether a path is an existing file that is not a folder; empty: the file
///              system's answer (a test counts the lookups)
std::vector<MtllibName> mtllib_names(
    const std::string& bytes, const MtllibLine& line, const std::filesystem::path& obj_folder,
    const std::function<bool(const std::filesystem::path&)>& probe = {});

/// A replacement of the bytes [begin, end).
struct TextEdit {
  std::size_t begin = 0, end = 0;
  std::string text;
};

/// The edits that make the mtllib lines of `bytes` (the OBJ file `input_path`) name the same
/// files from the folder of `output_path`: each relative name becomes the path of the same file
/// relative to the output's folder (folders compared and related with links resolved, '/' as
/// separator); absolute names stay. A name that is no file from the input's folder stays as
/// written, with a warning "<input>: line <n>: ..." appended to `warnings` (when given); so
/// does a rewritten path with a space where the name had none (readers that split the line at
/// spaces, as the spec does, cannot read it). No edits, no warnings when both files are in
/// the same folder, when input_path is empty (unknown), or when there is no mtllib line.
std::vector<TextEdit> material_library_edits(const std::string& bytes,
                                             const std::vector<MtllibLine>& lines,
                                             const std::string& input_path,
                                             const std::string& output_path,
                                             std::vector<std::string>* warnings);

/// `bytes` with `edits` (in file order, not overlapping) applied.
std::string apply_edits(const std::string& bytes, const std::vector<TextEdit>& edits);

/// The OBJ file `input_path`'s bytes with its mtllib lines rewritten for `output_path`
/// (material_library_edits); the bytes themselves when nothing changes.
std::string relocate_material_libraries(const std::string& bytes, const std::string& input_path,
                                        const std::string& output_path,
                                        std::vector<std::string>* warnings);

/// Whether two paths are in the same folder (folders compared with links resolved).
bool same_folder(const std::string& a, const std::string& b);

/// The path of `target` relative to `folder`, both as the process finds them (relative to the
/// current folder or absolute): links in the folders resolved, the target's file name kept;
/// '/' as separator. The absolute path when there is no relative one.
std::string path_from_folder(const std::filesystem::path& target, const std::filesystem::path& folder);

}  // namespace shellcontract
