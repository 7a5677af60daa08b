// The files a mesh file reads or names besides itself (docs/design/output-safety.md, "Files the
// input needs"): an OBJ's material libraries and the images they name, a PLY's texture files, a
// glTF's external buffers and images. No output may be one of them (output_check.cpp): a log
// written over an OBJ's .mtl destroys the user's materials, and a summary over a .gltf's buffer
// leaves the .gltf unreadable, though neither file is the input itself.
#pragma once

#include <string>

#include "shellcontract/output_files.hpp"

namespace shellcontract {

// InputDependency and input_dependencies() are public (shellcontract/output_files.hpp): a
// program that writes files beside a mesh (the sweep's tables) holds them as the outputs' check
// does.

/// A URI reference's path with its %XX escapes decoded, as a viewer finds the file ("a%20b.png"
/// is "a b.png"); other characters as they are.
std::string percent_decoded(const std::string& uri);

}  // namespace shellcontract
