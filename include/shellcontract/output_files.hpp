// The check of a command's output files before any work (docs/design/output-safety.md), shared
// by the CLI (cli/output_paths.hpp adds its export folder) and the Python module (contract()'s
// checkpoint=, write_mesh's target).
#pragma once

#include <string>
#include <vector>

namespace shellcontract {

/// A file a command writes or reads, and the option that names it in messages ("-o",
/// "--summary"; "INPUT" or "--regions" for an input; Python's "checkpoint"). An input named
/// "INPUT" is a mesh file: the files it reads or names (its .mtl and textures, a glTF's buffers
/// and images) are inputs too.
struct NamedFile {
  std::string option;
  std::string path;
};

/// One file a mesh file needs besides itself, whether or not it exists.
struct InputDependency {
  std::string path;  ///< as the process finds it: the reader's resolution of the name
  /// What it is to the input, for messages: "the material library that 'c.obj' reads (mtllib,
  /// line 1)".
  std::string role;
};

/// The files that the mesh file `path` reads or names (docs/design/output-safety.md, "Files the
/// input needs"), by its extension, resolved as its readers resolve them, which
/// check_output_files refuses as outputs of an "INPUT" mesh; for a program that writes files of
/// its own beside a mesh (the sweep's tables):
/// - .obj: each mtllib name (one that names no file too), and the images of each library that
///   can be read (every texture key, not only the map_Kd that the glTF export uses); a library
///   named again (by any spelling of the same file) is listed and read once, at its first
///   mtllib line;
/// - .ply: each `comment TextureFile` path;
/// - .gltf, .glb: every path where an external buffer was looked for (the file's folder, then the
///   current one) and each external image URI, percent-decoded, from the file's folder.
/// A file named but missing is listed: an output that created it would change what the input
/// means. Nothing for other formats. Never throws for the files' contents: a file the reader will
/// refuse gives what could be made out before the problem.
std::vector<InputDependency> input_dependencies(const std::string& path);

/// Checks a command's outputs before any work, so that a run does not fail after minutes because
/// its output folder is missing, nor write over its own input: by file identity (device and
/// inode; for a file that does not exist yet, its folder's and its name), so that hard links,
/// symbolic links and bind mounts are seen through, no output may be an input (nor a file the
/// "INPUT" mesh reads or names, existing or not) or another output;
/// an existing output must be a writable regular file (a folder, device, FIFO or socket is never
/// replaced), and not one of another user in a sticky folder that the caller could not replace
/// (EPERM); each output's folder is probed by creating and removing a file with a name of the
/// output's temporary's length (a missing or read-only folder, a parent that is a file, a name
/// or a path too long). A symbolic link is checked as its target (which the write replaces,
/// keeping the link), except one of another user in a sticky folder, which is refused (EACCES);
/// a descriptor path (/dev/stderr, /dev/fd/N) must be open for writing and is never a checkpoint
/// (docs/design/output-safety.md, "Symbolic links and streams").
/// Creates nothing that stays.
/// @throws UsageError naming the option, the path and the reason; an OutputFileError
///         (shellcontract/file_error.hpp) with the errno where the file system refused (a
///         missing or read-only folder: ENOENT, EACCES; a folder in the output's place: EISDIR)
void check_output_files(const std::vector<NamedFile>& outputs, const std::vector<NamedFile>& inputs);

/// Refuses an existing `path` that no writer of the library replaces: a folder (EISDIR), a
/// device, FIFO or socket (FileSystemFailure::NO_ERRNO): "cannot write 'PATH': it is a folder",
/// "cannot write 'PATH': it exists and is not a regular file (...)". Every writer checks it
/// (write_mesh_atomic before the extension: /dev/null has none, and is refused for what it is);
/// a caller that checks the name in its own way first (the Python module's write_mesh with
/// like=) calls it before that. Only stat: nothing is opened.
/// @throws OutputFileError (shellcontract/file_error.hpp)
void refuse_special_output(const std::string& path);

}  // namespace shellcontract
