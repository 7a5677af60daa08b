// The size of a run's .glb, known before the run (docs/design/export.md, "Size"): the buffer as
// write_gltf_animation lays it out, padding included, and the JSON chunk bounded by an allowance
// per entry. glTF's binary container stores its lengths as 32-bit numbers, so no .glb may exceed
// 4 GiB - 1 bytes; tinygltf's writer stores a wrapped length without a word (a corrupt file), so
// the writer checks the file's true size before its first byte, and the CLI refuses a --gltf
// whose bound is over it before the run.
#pragma once

#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>

#include "shellcontract/export.hpp"

namespace shellcontract::gltf {

/// The bytes of the buffer write_gltf_animation fills for `a` with `frames` frames (a.frames is
/// not read) on `vertices` glTF vertices (the split's): each view's alignment padding included,
/// so an upper bound.
std::size_t buffer_capacity(const GltfAnimation& a, std::size_t vertices, std::size_t frames);

/// The glTF vertices of `layout`: its frame 0's rows, and the copies of the vertices that a
/// seam, a hard edge, a colour or a region's rim splits (split_vertices). `layout` holds frame 0
/// (later frames are not read), the faces and the input's attributes.
std::size_t glb_vertices(const GltfAnimation& layout);

/// An upper bound of the size of the .glb of `layout` with `frames` frames on `vertices` glTF
/// vertices (glb_vertices): the 20 bytes of the header and the JSON chunk's header, the JSON
/// chunk, the BIN chunk's 8 and buffer_capacity. `layout` holds the faces, the input's
/// attributes and materials, and one entry per field in frame_fields and colour_fields (their
/// values are not read).
std::uint64_t glb_size_bound(const GltfAnimation& layout, std::size_t frames, std::size_t vertices);

/// The largest .glb written: 4 GiB - 1 bytes (its lengths are 32-bit), or the test hook's.
std::uint64_t glb_max_bytes();

/// Test hook: a lower limit, so that a test meets it with a small file (no test writes 4 GiB);
/// 0 restores the real one. Not thread-safe: set it before any writing.
void set_glb_max_bytes_for_test(std::uint64_t bytes);

/// Writes `model` (one buffer, the BIN chunk) as a .glb into `out` through tinygltf, after a
/// check of the file's true size: the BIN chunk's is known, the JSON chunk's once tinygltf has
/// serialized it (its chunk header is held back until then). Returns the bytes written.
/// @throws UsageError naming `path` when the file would exceed glb_max_bytes(): nothing is
///         written into `out` then
std::size_t write_glb(const std::string& path, const tinygltf::Model& model, std::ostream& out);

/// "3.9 GiB", "612 MiB", "48 KiB" or "900 bytes": a size for a message.
std::string size_text(std::uint64_t bytes);

}  // namespace shellcontract::gltf
