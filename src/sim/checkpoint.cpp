#include "sim/checkpoint.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <limits>
#include <new>
#include <stdexcept>
#include <type_traits>

#include "core/memory_error.hpp"
#include "core/resource_file_error.hpp"
#include "mesh/file_safety.hpp"
#include "mesh/file_start.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/file_error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/version.hpp"
#include "sim/checkpoint_stream.hpp"

namespace shellcontract {
namespace {

using detail::Reader;
using detail::Writer;

// The file: MAGIC, FORMAT, the fields in the order of Writer calls below, then an FNV-1a hash of
// everything before it (a truncated or damaged file is refused, not resumed into another run).
// Numbers are the machine's own bytes: a checkpoint moves between machines of one architecture
// (the sweep's workers), where the doubles read back bit for bit.
// Format 2 added the run's inputs (RunInput) after the input's hash. Format 1 is still read:
// the tool's version did not change with it, so checkpoints of format 1 can be waiting to be
// resumed (a sweep's); check_checkpoint_files refuses them only where there is a file to check.
// Format 3 added the saving run's interval between saves after the log (format 2 reads as 0).
// Format 4 is format 3 with the log's length and FNV-1a in place of the log, which is in the
// file beside (CheckpointLogFile). Format 5 is format 4 with the V/V0 history's length and
// FNV-1a in place of the history (one double a frame so far), which is in a file beside too: a
// checkpoint then does not grow with the frames run. A checkpoint that holds them (a run's first
// save) is still written as format 3.
constexpr char MAGIC[] = "SHELLCONTRACT-CHECKPOINT\n";
constexpr std::uint32_t FORMAT_HISTORY_BESIDE = 5;
constexpr std::uint32_t FORMAT_LOG_BESIDE = 4;
constexpr std::uint32_t FORMAT = 3;
constexpr std::uint32_t FORMAT_WITHOUT_SAVE_EVERY = 2;
constexpr std::uint32_t FORMAT_WITHOUT_INPUTS = 1;

bool result_neutral(const std::string& name) {
  const std::vector<std::string>& neutral = result_neutral_options();
  return std::find(neutral.begin(), neutral.end(), name) != neutral.end();
}

static_assert(std::is_trivially_copyable_v<RunTotals>,
              "RunTotals is saved as its bytes; a member that is not (a vector) needs a field");

void write_contact(Writer& w, const Contact& c) {
  w.pod(static_cast<std::int32_t>(c.kind));
  w.pod(c.pair);
  w.pod(c.v);
  for (int k = 0; k < 4; ++k) w.pod(c.weights(k));
  for (int k = 0; k < 3; ++k) w.pod(c.normal(k));
  w.pod(c.side);
}

/// A contact's bytes in the file (write_contact): its kind, pair, 4 vertices, 4 weights, normal
/// and side.
constexpr std::size_t CONTACT_BYTES = sizeof(std::int32_t) + sizeof(std::array<int, 2>) +
                                      sizeof(std::array<int, 4>) + 8 * sizeof(double);

Contact read_contact(Reader& r) {
  Contact c;
  c.kind = static_cast<CcdPrimitive>(r.pod<std::int32_t>());
  c.pair = r.pod<std::array<int, 2>>();
  c.v = r.pod<std::array<int, 4>>();
  for (int k = 0; k < 4; ++k) c.weights(k) = r.pod<double>();
  for (int k = 0; k < 3; ++k) c.normal(k) = r.pod<double>();
  c.side = r.pod<double>();
  return c;
}

std::string describe(const OptionValues& o, const std::string& name) {
  for (const auto& [n, v] : o)
    if (n == name) return v.empty() ? "unset" : v;
  return "unset";
}

/// The most bytes a checkpoint is read with: the machine's memory. A checkpoint is a run's state,
/// which a run resuming it holds in memory (and more besides), so one larger than the memory
/// cannot be resumed here; reading it anyway ended in "out of memory", naming no file. (The
/// mesh, which would bound it better, is read after the checkpoint, which names it.)
std::uint64_t checkpoint_byte_cap() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return std::numeric_limits<std::uint64_t>::max();
  return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page);
}

/// The bytes of the checkpoint `path`, or InputError naming it. Its magic is read first: a file
/// that is no checkpoint (a mesh, a log, a huge sparse file given by mistake) is refused after
/// its first bytes, whatever its size; one larger than checkpoint_byte_cap before it is read.
std::string checkpoint_bytes(const std::string& path) {
  std::string start;
  std::uint64_t size = 0;
  try {
    // A regular file only: a folder is "it is a folder", not a stream's read error.
    start = read_regular_file_start(path, sizeof MAGIC - 1);
    size = regular_file_size(path);
  } catch (const InputError& e) {
    rethrow_input_error_as(e, "checkpoint " + std::string(e.what()));  // errno and path kept
  } catch (const ResourceFileError& e) {
    // No descriptor (or kernel memory) to open it: a checkpoint not read, exit code 2 as for a
    // failing disk, not the 3 of an input mesh. A sweep keeps a checkpoint it could not read and
    // resumes from it later; it tells such a read from a refusal of the contents by the exit
    // code 2 and the "cannot open file" of the message (docs/design/sweeps.md, "Jobs").
    throw InputFileError("checkpoint " + std::string(e.what()), e.error_number(), e.path());
  }
  if (start != MAGIC)
    throw InputError("checkpoint " + printable(path) + ": not a shellcontract checkpoint");
  const std::uint64_t cap = checkpoint_byte_cap();
  if (size > cap)
    throw InputFileError("checkpoint " + printable(path) + ": file too large: " +
                             std::to_string(size) + " bytes, more than this machine's memory (" +
                             std::to_string(cap) + " bytes), which a run resuming it would need",
                         EFBIG, path);
  try {
    return read_regular_file(path, cap);
  } catch (const InputError& e) {
    rethrow_input_error_as(e, "checkpoint " + std::string(e.what()));
  } catch (const ResourceFileError& e) {  // as above
    throw InputFileError("checkpoint " + std::string(e.what()), e.error_number(), e.path());
  } catch (const std::bad_alloc&) {
    throw OutOfMemoryError("checkpoint " + printable(path) + ": out of memory while reading its " +
                           std::to_string(size) + " bytes");
  }
}

}  // namespace

// The build and the kernels (shellcontract/version.hpp): a checkpoint resumed by another build,
// or on a CPU whose kernels round otherwise, would continue into a result that is neither run's.
const char* checkpoint_tool_version() {
  static const std::string identity = tool_identity();
  return identity.c_str();
}

std::uint64_t fnv1a(const void* data, std::size_t n, std::uint64_t h) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}

std::uint64_t mesh_hash(const Mesh& mesh) {
  std::uint64_t h = fnv1a("mesh", 4);
  for (VertexIndex v : mesh.vertices()) {
    const Point3& p = mesh.point(v);
    const double c[3] = {p.x(), p.y(), p.z()};
    h = fnv1a(c, sizeof c, h);
  }
  for (FaceIndex f : mesh.faces())
    for (VertexIndex v : vertices_around_face(mesh.halfedge(f), mesh)) {
      const std::uint32_t i = v.idx();
      h = fnv1a(&i, sizeof i, h);
    }
  // A welded input (mesh_io.hpp, "Seams") is also its input's corners: the same welded mesh
  // from a file split otherwise writes other outputs. (A mesh closed as given hashes as before.)
  if (has_welded_seams(mesh))
    for (const auto& corners : input_faces(mesh))
      for (const std::size_t c : corners) {
        const std::uint64_t i = c;
        h = fnv1a(&i, sizeof i, h);
      }
  return h;
}

const std::vector<std::string>& result_neutral_options() {
  // Not speculative-broad-phase: its queried pairs come after the grid's, so on and off order
  // the same pairs otherwise, and a run with contacts ends elsewhere (docs/design/self-collision.md).
  static const std::vector<std::string> names{"threads"};
  return names;
}

OptionValues given_options(const RunOptions& options) {
  OptionValues out;
  for (const OptionSpec& o : run_option_table())
    if (options.given.count(option_field(o.name)) && !result_neutral(o.name))
      out.emplace_back(o.name, o.get(options));
  return out;
}

OptionValues resolved_options(RunOptions options) {
  resolve_run_options(options);
  OptionValues out;
  for (const OptionSpec& o : run_option_table())
    if (!result_neutral(o.name)) out.emplace_back(o.name, o.get(options));
  return out;
}

namespace {

/// The options of `now` (resolved_options) whose values differ from the checkpoint's, each as
/// "`field` VALUE (the checkpoint's: THEIRS)"; empty when they are the same.
std::string options_differing(const Checkpoint& c, const OptionValues& now) {
  const auto given_as_arrays = [&](const std::string& name) {
    for (const RunInput& in : c.inputs)
      if (in.arrays && in.option == option_field(name)) return true;
    return false;
  };
  // A face-list or weights file is compared by its contents (check_checkpoint_files), as the mesh
  // is: its path may differ (a copy, another machine, Python's temporary file of its arrays).
  const auto compared = [](const std::string& name, const std::string& value) {
    const bool file = (name == "regions" && !value.empty() && value != "auto" && value != "none" &&
                       value != "weights") ||
                      (name == "region-weights" && !value.empty());
    return file ? std::string("a file") : value.empty() ? std::string("unset") : value;
  };
  const auto theirs = [&](const std::string& name) {
    return given_as_arrays(name) ? std::string("given as arrays")
                                 : printable(describe(c.resolved, name));
  };
  std::string differ;
  for (const auto& [name, value] : now) {
    const std::string then = describe(c.resolved, name);
    if (compared(name, then == "unset" ? "" : then) != compared(name, value))
      // `field`, so that each front end spells the option its own way (spell_options).
      differ += (differ.empty() ? "" : ", ") + ("`" + option_field(name) + "` " + (value.empty() ? "unset" : value) +
                                                 " (the checkpoint's: " + theirs(name) + ")");
  }
  if (differ.empty() && now.size() != c.resolved.size())
    differ = "the checkpoint lists other options";
  return differ;
}

}  // namespace

RunOptions options_for_resume(const Checkpoint& c, const RunOptions& command_line) {
  // An option the checkpoint's run was given as arrays (Python) holds a temporary file or
  // nothing in the checkpoint: only the caller can give it again.
  for (const RunInput& in : c.inputs)
    if (in.arrays && !command_line.given.count(in.option))
      throw UsageError("the checkpoint's `" + in.option +
                       "` were given as arrays (from Python), which it does not hold: give the same `" +
                       in.option + "` again");
  const auto given_as_arrays = [&](const std::string& name) {
    for (const RunInput& in : c.inputs)
      if (in.arrays && in.option == option_field(name)) return true;
    return false;
  };
  RunOptions options;
  for (const auto& [name, value] : c.given)
    // Weights given as numbers have no text (format 1 recorded them as an empty file name).
    if (!given_as_arrays(name) && !(name == "region-weights" && value.empty()))
      set_run_option(options, name, value);
  for (const OptionSpec& o : run_option_table())
    if (command_line.given.count(option_field(o.name))) {
      if (o.name == "region-weights" && command_line.region_weight_file.empty()) {
        // Weights given as numbers (Python's region_weights=W) have no text to set them by.
        options.vertex_weights = command_line.vertex_weights;
        options.given.insert("region_weights");
        continue;
      }
      o.set(options, o.get(command_line));
    }
  OptionValues now;
  try {
    now = resolved_options(options);
  } catch (const UsageError& e) {
    // An option given that excludes one of the checkpoint's: the mismatch is the user's news,
    // the exclusion only its form.
    std::string own;
    for (const auto& [name, value] : c.given)
      own += (own.empty() ? "--" : ", --") + name + " " + printable(value, 60);
    throw UsageError("the checkpoint was written with other options: the options given do not go with its own (" +
                     own + "): " + e.what());
  }
  const std::string differ = options_differing(c, now);
  if (!differ.empty())
    throw UsageError("the checkpoint was written with other options: " + differ);
  return options;
}

void check_checkpoint_input(const Checkpoint& c, const std::string& path, const Mesh& mesh) {
  if (c.version != checkpoint_tool_version())
    throw InputError("checkpoint written by shellcontract " + c.version + ", this is " +
                     checkpoint_tool_version() + ": resume it with that build and kernels");
  if (mesh_hash(mesh) == c.input_hash) return;
  // A run of arrays (Python) has no file to name or to have changed; `path` may name arrays too.
  const bool plural = path.rfind("the vertices and faces", 0) == 0;
  const std::string given = path + (plural ? " are" : " is");
  if (c.input == ARRAYS_INPUT)
    throw InputError("the checkpoint is of another input: " + given +
                     " not the mesh it was written for (it was run on vertices and faces given as "
                     "arrays: give the same arrays)");
  throw InputError("the checkpoint is of another input: " + given + " not the mesh " + c.input +
                   " it was written for (or that file has changed)");
}

void check_checkpoint_fits(const Checkpoint& c, const Mesh& mesh, const RunOptions& options) {
  check_checkpoint_input(c, "the mesh given", mesh);
  const std::string differ = options_differing(c, resolved_options(options));
  if (!differ.empty())
    throw InputError("the checkpoint does not fit this run: it was written with other options: " +
                     differ);
}

void write_checkpoint(const std::string& path, const Checkpoint& c, const LogBeside* beside,
                      const LogBeside* history) {
  if (history && !beside)
    throw std::logic_error("write_checkpoint: a history beside goes with a log beside");
  Writer w;
  w.bytes().append(MAGIC, sizeof MAGIC - 1);
  w.pod(history ? FORMAT_HISTORY_BESIDE : beside ? FORMAT_LOG_BESIDE : FORMAT);
  w.text(c.version);
  w.text(c.input);
  w.pod(c.input_hash);
  w.size(c.inputs.size());
  for (const RunInput& in : c.inputs) {
    w.text(in.option);
    w.text(in.file);
    w.pod(static_cast<std::uint8_t>(in.arrays));
    w.pod(in.hash);
  }
  w.options(c.given);
  w.options(c.resolved);
  const SimulatorState& s = c.sim;
  w.pod(static_cast<std::int64_t>(s.frame));
  w.pod(s.volume_ratio);
  w.pod(static_cast<std::uint8_t>(s.stop_volume_reached));
  w.matrix(s.x);
  w.matrix(s.v);
  w.list(s.held_by_contact);
  w.list(s.dimple_sizes);
  w.pod(static_cast<std::uint8_t>(s.has_collision));
  w.size(s.collision.contact_cache.size());
  for (const Contact& k : s.collision.contact_cache) write_contact(w, k);
  w.matrix(s.collision.correction);
  w.vector(s.collision.skin);
  const RunProgress& p = c.progress;
  if (history) {
    w.pod(history->size);
    w.pod(history->hash);
  } else {
    w.list(p.history);
  }
  w.pod(p.min_volume_ratio);
  w.pod(p.totals);
  w.pod(static_cast<std::int64_t>(p.new_intersections));
  w.pod(static_cast<std::int32_t>(p.status));
  w.text(p.message);
  w.pod(static_cast<std::int64_t>(p.frame_target_reached));
  w.pod(p.last_pairs);
  if (beside) {
    w.pod(beside->size);
    w.pod(beside->hash);
  } else {
    w.text(c.log);
  }
  w.pod(static_cast<std::int64_t>(c.save_every));
  w.pod(fnv1a(w.bytes().data(), w.bytes().size()));
  write_text_atomic(path, w.bytes());
}

Checkpoint read_checkpoint(const std::string& path) {
  const std::string bytes = checkpoint_bytes(path);
  Reader r(bytes, path);
  if (bytes.compare(0, sizeof MAGIC - 1, MAGIC) != 0)  // replaced since its magic was read
    throw InputError("checkpoint " + printable(path) + ": not a shellcontract checkpoint");
  std::string magic(sizeof MAGIC - 1, '\0');
  r.take(magic.data(), magic.size());
  if (bytes.size() < sizeof(std::uint64_t) + magic.size()) r.fail("truncated");
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + bytes.size() - sizeof stored, sizeof stored);
  if (fnv1a(bytes.data(), bytes.size() - sizeof stored) != stored)
    r.fail("its checksum does not match (truncated or damaged)");
  const auto format = r.pod<std::uint32_t>();
  if (format != FORMAT_HISTORY_BESIDE && format != FORMAT_LOG_BESIDE && format != FORMAT &&
      format != FORMAT_WITHOUT_SAVE_EVERY && format != FORMAT_WITHOUT_INPUTS)
    r.fail("another checkpoint format");
  Checkpoint c;
  c.version = r.text();
  c.input = r.text();
  c.input_hash = r.pod<std::uint64_t>();
  c.inputs_recorded = format != FORMAT_WITHOUT_INPUTS;
  if (c.inputs_recorded) {
    // Two texts' lengths, a flag and a hash each.
    c.inputs.resize(r.count(2 * sizeof(std::uint64_t) + 1 + sizeof(std::uint64_t), "inputs"));
    for (RunInput& in : c.inputs) {
      in.option = r.text();
      in.file = r.text();
      in.arrays = r.pod<std::uint8_t>() != 0;
      in.hash = r.pod<std::uint64_t>();
    }
  }
  c.given = r.options();
  c.resolved = r.options();
  SimulatorState& s = c.sim;
  s.frame = r.int_value("a frame");
  s.volume_ratio = r.pod<double>();
  s.stop_volume_reached = r.pod<std::uint8_t>() != 0;
  s.x = r.matrix();
  s.v = r.matrix();
  s.held_by_contact = r.list<char>();
  s.dimple_sizes = r.list<int>();
  s.has_collision = r.pod<std::uint8_t>() != 0;
  s.collision.contact_cache.resize(r.count(CONTACT_BYTES, "contacts"));
  for (Contact& k : s.collision.contact_cache) k = read_contact(r);
  s.collision.correction = r.matrix();
  s.collision.skin = r.vector();
  RunProgress& p = c.progress;
  LogBeside history;
  c.history_beside = format == FORMAT_HISTORY_BESIDE;
  if (c.history_beside) {
    history.size = r.pod<std::uint64_t>();
    history.hash = r.pod<std::uint64_t>();
    // One value a frame: a frame's int, not a count whose bytes would overflow.
    if (history.size > static_cast<std::uint64_t>(std::numeric_limits<int>::max()) + 1)
      r.fail("a volume history of " + std::to_string(history.size) + " values");
  } else {
    p.history = r.list<double>();
  }
  p.min_volume_ratio = r.pod<double>();
  p.totals = r.pod<RunTotals>();
  p.new_intersections = static_cast<long>(r.pod<std::int64_t>());
  p.status = static_cast<RunStatus>(r.pod<std::int32_t>());
  p.message = r.text();
  p.frame_target_reached = r.int_value("a target frame");
  p.last_pairs = r.pod<std::int64_t>();
  LogBeside beside;
  c.log_beside = format == FORMAT_LOG_BESIDE || format == FORMAT_HISTORY_BESIDE;
  if (c.log_beside) {
    beside.size = r.pod<std::uint64_t>();
    beside.hash = r.pod<std::uint64_t>();
  } else {
    c.log = r.text();
  }
  if (format >= FORMAT) {
    c.save_every = r.int_value("an interval between saves");
    if (c.save_every < 0) r.fail("a negative interval between saves");
  }
  if (r.position() + sizeof stored != bytes.size()) r.fail("trailing bytes");
  // Another version's fields follow its own rules (its options, its state): refused as another
  // version's here, before they are judged by this one's (as "edited or damaged").
  if (c.version != checkpoint_tool_version())
    throw InputError("checkpoint " + printable(path) + " written by shellcontract " +
                     printable(c.version, 120) + ", this is " + checkpoint_tool_version() +
                     ": resume it with that build and kernels");
  if (c.history_beside) p.history = read_history_beside(path, history);
  check_checkpoint_fields(c, path);
  if (c.log_beside) c.log = read_log_beside(path, beside);
  c.path = path;
  return c;
}

}  // namespace shellcontract
