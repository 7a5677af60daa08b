// Checks of the files a command will write, made before any work: a run must not fail after
// minutes of simulation because its output folder is missing, nor write JSON over its own mesh.
#pragma once

#include <string>
#include <vector>

namespace shellcontract::cli {

/// One file a command will write and the option that names it.
struct PlannedOutput {
  std::string option;  ///< e.g. "-o" or "--summary"
  std::string path;
};

/// Checks that every planned output is distinct from the others and from the input (the same
/// file reached by different spellings counts as the same), that its folder exists and is
/// writable, and that it is not an existing folder.
/// @throws UsageError naming the option and the path
void check_planned_outputs(const std::vector<PlannedOutput>& outputs, const std::string& input);

}  // namespace shellcontract::cli
