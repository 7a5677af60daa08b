// The files a checkpointed run reads besides its mesh (shellcontract/checkpoint.hpp, RunInput):
// their contents' hashes, recorded when the run starts and compared when it resumes, so that a
// face list or weights file edited in between is refused instead of resumed into a run that
// matches neither.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh/file_safety.hpp"
#include "mesh/file_start.hpp"
#include "shellcontract/checkpoint.hpp"
#include "shellcontract/error.hpp"
#include "sim/checkpoint.hpp"

namespace shellcontract {
namespace {

/// How a message names an input: "`regions` reg.txt", or "the `regions` given as arrays".
std::string named(const RunInput& in) {
  return in.arrays ? "the `" + in.option + "` given as arrays" : "`" + in.option + "` " + printable(in.file);
}

}  // namespace

std::vector<RunInput> run_inputs(const RunOptions& options) {
  std::vector<RunInput> out;
  // Hashed a piece at a time, not read whole: this runs before the mesh, and so before the
  // reader that bounds the file by what the mesh can need; a file of any size costs a piece.
  const auto file = [&](const std::string& field, const std::string& path) {
    std::uint64_t h = fnv1a(nullptr, 0);
    read_regular_file_pieces(path, [&](const char* bytes, std::size_t n) {  // InputError naming it
      h = fnv1a(bytes, n, h);
    });
    out.push_back({field, path, false, h});
  };
  if (options.regions == RegionSource::File) file("regions", options.region_file);
  if (!options.region_weight_file.empty()) {
    file("region_weights", options.region_weight_file);
  } else if (!options.vertex_weights.empty()) {
    const std::vector<double>& w = options.vertex_weights;
    out.push_back({"region_weights", "", true, fnv1a(w.data(), sizeof(double) * w.size())});
  }
  return out;
}

void check_checkpoint_files(const Checkpoint& c, const std::vector<RunInput>& inputs) {
  if (inputs.empty()) return;
  if (!c.inputs_recorded)
    throw InputError("the checkpoint was written before checkpoints recorded the files a run reads besides "
                     "its mesh, so " + named(inputs.front()) +
                     " cannot be checked against what its run read: start the run again, without resuming");
  for (const RunInput& now : inputs) {
    const RunInput* then = nullptr;
    for (const RunInput& in : c.inputs)
      if (in.option == now.option) then = &in;
    if (then && then->hash == now.hash) continue;
    std::string what;
    if (!then)
      what = named(now) + " was not an input of its run";
    else if (!now.arrays && !then->arrays && then->file == now.file)
      what = named(now) + " has changed since the checkpoint was written";
    else if (now.arrays && then->arrays)
      what = named(now) + " are not those its run was given";
    else
      what = named(now) + (now.arrays ? " are" : " is") + " not what its run read (" + named(*then) + ")";
    throw InputError("the checkpoint is of another input: " + what);
  }
}

}  // namespace shellcontract
