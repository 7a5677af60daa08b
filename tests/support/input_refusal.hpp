// What read_input_mesh says of a file it refuses, for tests that compare the message whole.
#pragma once

#include <string>

#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract::test {

/// read_input_mesh's refusal of the file at `path` (its InputError's text), or "(no error)".
inline std::string input_refusal(const std::string& path) {
  try {
    read_input_mesh(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace shellcontract::test
