#include "output_paths.hpp"

#include <unistd.h>

#include <filesystem>
#include <system_error>

#include "shellcontract/core/error.hpp"

namespace shellcontract::cli {
namespace {

namespace fs = std::filesystem;

/// The absolute, normalized path (symbolic links resolved where the file or folder exists).
fs::path identity(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return ec ? fs::absolute(path).lexically_normal() : p;
}

}  // namespace

void check_planned_outputs(const std::vector<PlannedOutput>& outputs, const std::string& input) {
  const fs::path in = identity(input);
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const PlannedOutput& o = outputs[i];
    if (o.path.empty()) throw UsageError(o.option + ": empty file name");
    const fs::path p = identity(o.path);
    if (p == in)
      throw UsageError(o.option + " " + o.path + " is the input file; choose another name");
    for (std::size_t j = 0; j < i; ++j)
      if (identity(outputs[j].path) == p)
        throw UsageError(o.option + " " + o.path + " is also the file of " + outputs[j].option +
                         "; each output needs its own file");
    std::error_code ec;
    if (fs::is_directory(p, ec))
      throw UsageError(o.option + " " + o.path + " is a folder, not a file");
    const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    if (!fs::is_directory(dir, ec))
      throw UsageError(o.option + " " + o.path + ": the folder " + dir.string() +
                       " does not exist");
    if (::access(dir.c_str(), W_OK) != 0)
      throw UsageError(o.option + " " + o.path + ": the folder " + dir.string() +
                       " is not writable");
  }
}

}  // namespace shellcontract::cli
