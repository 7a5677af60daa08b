// One key for every spelling of a file ("a.mtl", "./a.mtl", a link to it), so that a file that an
// input names many times is read once: an OBJ may name one material library on a thousand mtllib
// lines, and a hundred materials may name one texture of many megabytes.
#pragma once

#include <sys/stat.h>

#include <filesystem>
#include <string>

namespace shellcontract {

/// The device and inode of the file `path` leads to (links followed) when it can be found; else
/// its lexically normal path. The two kinds never compare equal.
inline std::string file_key(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0)
    return "inode " + std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
  return "path " + std::filesystem::path(path).lexically_normal().string();
}

}  // namespace shellcontract
