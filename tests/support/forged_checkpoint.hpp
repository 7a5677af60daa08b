// A checkpoint as anyone holding the file can make it: a real one with a field changed and its
// checksum recomputed. The checksum (src/sim/checkpoint.cpp) is FNV-1a over every byte before
// it, stored as the file's last 8 bytes; it is no key, so such a file passes it, and only the
// reader's checks of the fields themselves stand between it and the run.
#pragma once

#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <stdexcept>
#include <string>

#include "sim/checkpoint.hpp"

namespace shellcontract::test {

inline std::string checkpoint_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// `bytes` with the last 8 bytes set to the FNV-1a (64 bits) of the rest, in the machine's byte
/// order: the seal a checkpoint ends with. Written out here, not taken from the library, so that
/// the forgery does not depend on the code under test.
inline std::string resealed(std::string bytes) {
  if (bytes.size() < 8) throw std::invalid_argument("resealed: not a checkpoint");
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < bytes.size() - 8; ++i) {
    h ^= static_cast<unsigned char>(bytes[i]);
    h *= 1099511628211ull;
  }
  std::memcpy(bytes.data() + bytes.size() - 8, &h, 8);
  return bytes;
}

/// Writes to `to` the checkpoint `from` with `edit` applied to its fields, written by the tool's
/// own writer (which seals it as any checkpoint).
inline void forge_checkpoint(const std::string& from, const std::string& to,
                             const std::function<void(Checkpoint&)>& edit) {
  Checkpoint c = read_checkpoint(from);
  edit(c);
  write_checkpoint(to, c);
}

/// Writes to `to` the checkpoint `from` with the 8 bytes of `marker` (a value written there
/// through forge_checkpoint, found once in the file) replaced by `value`, then resealed: for a
/// value that the fields' own types cannot hold (a frame past int's range).
inline void forge_int64(const std::string& from, const std::string& to, std::int64_t marker,
                        std::int64_t value) {
  std::string bytes = checkpoint_bytes(from);
  const std::string m(reinterpret_cast<const char*>(&marker), 8);
  const std::size_t at = bytes.find(m);
  if (at == std::string::npos || bytes.find(m, at + 1) != std::string::npos)
    throw std::invalid_argument("forge_int64: the marker is not in the file exactly once");
  std::memcpy(bytes.data() + at, &value, 8);
  std::ofstream(to, std::ios::binary | std::ios::trunc) << resealed(bytes);
}

}  // namespace shellcontract::test
