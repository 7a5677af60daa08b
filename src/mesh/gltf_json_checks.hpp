// Checks of a glTF's JSON text made before tinygltf parses it (gltf_reader.cpp, load_model):
// its nesting depth, which every recursive JSON reader of the program (tinygltf's extras and
// extensions, nlohmann's copies and dumps in gltf_json.cpp) must be able to take without running
// out of stack, and the members tinygltf reads leniently (asset's version, the default scene,
// every index, which it keeps as an int) or that the buffer callbacks need before tinygltf reads
// a buffer (each buffer's URI and byteLength). Private to src/mesh.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace shellcontract::gltf {

/// The deepest nesting of arrays and objects that a glTF's JSON may have. Real exporters' glTF
/// nests about ten levels (root, meshes, a mesh, its primitives, a primitive, its attributes, an
/// extension's object) and their extras a few more; the recursive readers each take a few hundred
/// bytes of stack a level, so this many levels stay far below any thread's stack.
constexpr std::size_t MAX_JSON_DEPTH = 512;

/// The byte (from `text`) of the '[' or '{' that opens level MAX_JSON_DEPTH + 1 outside strings,
/// or npos where the JSON nests no deeper than MAX_JSON_DEPTH. Malformed JSON (an unclosed
/// string, unbalanced brackets) is scanned all the same; its parser refuses it later.
std::size_t too_deep_at(const char* text, std::size_t size);

/// A buffer as the JSON declares it.
struct DeclaredBuffer {
  std::string uri;   ///< as written (percent-encoded); empty where there is none
  std::string file;  ///< the URI decoded as tinygltf decodes it for the file's name ('+': ' ')
  std::uint64_t byte_length = 0;
};

/// Refuses a JSON that nests deeper than MAX_JSON_DEPTH, an `asset.version` whose major version
/// is not 2 (or an `asset.minVersion` above 2.0), a `scene` that is not a scene index, and an
/// integer above INT_MAX or below 0 in a member that holds an index ("bad index:
/// nodes[0].mesh is 4294967296, ..."; outside extras and extensions); then returns the buffers.
/// JSON that does not parse is left to tinygltf (no buffers returned).
/// @param text the .gltf, or the .glb's JSON chunk, which starts at byte `first_byte` of the file
/// @throws InputError "<path>: <problem>: <details>"
std::vector<DeclaredBuffer> check_top_level(const std::string& path, const char* text,
                                            std::size_t size, std::size_t first_byte);

/// The buffers whose URI (as written, or decoded) is seen to name the external buffer file `file`
/// (a path as tinygltf asks for it: the URI ends it), in order; data URIs never.
std::vector<std::size_t> buffers_naming(const std::vector<DeclaredBuffer>& declared,
                                        const std::string& file);

/// The most bytes that the external buffer file `file` (a path as tinygltf asks for it) may
/// have, and for a message what says so: "buffer 0's byteLength of 1464 ('mesh.bin')".
std::pair<std::uint64_t, std::string> buffer_file_bound(const std::vector<DeclaredBuffer>& declared,
                                                        const std::string& file);

}  // namespace shellcontract::gltf
