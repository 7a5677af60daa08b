// The caller's side of saving a checkpoint (shellcontract/checkpoint.hpp), and the caller's log
// and the run's volume history kept beside the checkpoint (CheckpointLogFile): written whole into
// every save they made each save as large as the run so far, so a long run spent the square of
// its frames on saving.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>

#include "core/resource_file_error.hpp"
#include "mesh/file_safety.hpp"
#include "mesh/file_start.hpp"
#include "mesh/output_target.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/file_error.hpp"
#include "sim/checkpoint.hpp"
#include "sim/simulator.hpp"

namespace shellcontract {
namespace {

constexpr std::uint64_t FNV_BASIS = 1469598103934665603ull;

Checkpoint saved_checkpoint(const SavedRun& run, const RunOptions& options,
                            const CheckpointInfo& info) {
  Checkpoint c;
  c.version = checkpoint_tool_version();
  c.input = info.input;
  c.input_hash = info.input_hash;
  c.inputs = info.inputs;
  c.given = given_options(options);
  c.resolved = resolved_options(options);
  c.sim = run.sim.state();
  c.progress = run.progress;
  c.save_every = info.save_every;
  return c;
}

[[noreturn]] void cannot_write(const std::string& path, int error) {
  throw UsageError("cannot write '" + printable(path) + "': " + file_error_text(error));
}

}  // namespace

std::shared_ptr<const Checkpoint> load_checkpoint(const std::string& path) {
  return std::make_shared<const Checkpoint>(read_checkpoint(path));
}

int checkpoint_frame(const Checkpoint& c) { return c.sim.frame; }
const std::string& checkpoint_log(const Checkpoint& c) { return c.log; }
int checkpoint_save_every(const Checkpoint& c) { return c.save_every; }

// Named after the file a save replaces (a link's target), as the lock is: a run resumed through
// a link finds the rows a run naming the file itself wrote.
std::string checkpoint_log_path(const std::string& checkpoint) {
  return replaced_file(checkpoint) + ".log";
}
std::string checkpoint_history_path(const std::string& checkpoint) {
  return replaced_file(checkpoint) + ".history";
}

void write_checkpoint(const std::string& path, const SavedRun& run, const RunOptions& options,
                      const CheckpointInfo& info) {
  Checkpoint c = saved_checkpoint(run, options, info);
  c.log = info.log;
  write_checkpoint(path, c);
}

void write_checkpoint(const std::string& path, const SavedRun& run, const RunOptions& options,
                      const CheckpointInfo& info, CheckpointLogFile& log) {
  Checkpoint c = saved_checkpoint(run, options, info);
  if (log.beside()) {
    const auto [size, hash] = log.append();
    const auto [values, history_hash] = log.append_history(c.progress.history);
    const LogBeside beside{size, hash}, history{values, history_hash};
    write_checkpoint(path, c, &beside, &history);
  } else {
    c.log = log.log();  // the whole log and history, once: see CheckpointLogFile
    write_checkpoint(path, c);
  }
  log.committed();
}

namespace {

/// The first `size` bytes of the file beside the checkpoint `path`, `file`, whose FNV-1a is
/// `hash`; `what` names it in the messages ("log", "volume history").
std::string read_beside(const std::string& path, const std::string& file, const std::string& what,
                        std::uint64_t size, std::uint64_t hash) {
  const std::string start = "checkpoint " + printable(path) + ": its " + what + " ";
  const std::string why = " (the checkpoint keeps the run's " + what +
                          " in that file beside it: move or copy the checkpoint and its files "
                          "beside together)";
  std::string bytes;
  try {
    // Only the recorded length: bytes past it are not this checkpoint's (below), and a file made
    // larger (a wrong file copied over it, a huge sparse one) was read whole for nothing.
    bytes = read_regular_file_start(file, size);
  } catch (const InputError& e) {
    rethrow_input_error_as(e, start + e.what() + why);  // errno and path kept
  } catch (const ResourceFileError& e) {
    // Not read for want of a descriptor: exit code 2, as the checkpoint itself (checkpoint.cpp's
    // checkpoint_bytes says why).
    throw InputFileError(start + e.what() + why, e.error_number(), e.path());
  }
  if (bytes.size() < size)
    throw InputError(start + printable(file) + " holds " + std::to_string(bytes.size()) +
                     " bytes, fewer than the " + std::to_string(size) +
                     " the checkpoint was saved with (truncated, or another run's " + what + ")" +
                     why);
  // Bytes past the recorded length are a later save's that ended before its checkpoint was
  // renamed into place: not this checkpoint's (not read).
  if (fnv1a(bytes.data(), bytes.size()) != hash)
    throw InputError(start + printable(file) +
                     " is not the one the checkpoint was saved with (damaged, or another run's " +
                     what + ")" + why);
  return bytes;
}

}  // namespace

std::string read_log_beside(const std::string& path, const LogBeside& beside) {
  return read_beside(path, checkpoint_log_path(path), "log", beside.size, beside.hash);
}

std::vector<double> read_history_beside(const std::string& path, const LogBeside& beside) {
  const std::string bytes = read_beside(path, checkpoint_history_path(path), "volume history",
                                        beside.size * sizeof(double), beside.hash);
  std::vector<double> history(static_cast<std::size_t>(beside.size));
  std::memcpy(history.data(), bytes.data(), bytes.size());
  return history;
}

CheckpointLogFile::CheckpointLogFile(const std::string& checkpoint, const std::string& log,
                                     const Checkpoint* resumed)
    : log_(log) {
  log_file_.path = checkpoint_log_path(checkpoint);
  history_file_.path = checkpoint_history_path(checkpoint);
  // Resumed from this very file with its log beside: the log goes on there, after the length
  // the checkpoint records, and so does the history when it is beside too (format 5); a
  // history that format 4 held itself starts its file anew. Otherwise the files beside may be
  // what the checkpoint in place needs (another run's, the one resumed from when that is
  // elsewhere): left alone. "This very file" takes its files beside too: a hard link (or a
  // symbolic link) to the checkpoint under another name is the same file, but its files beside
  // are another run's, which an append would have taken for the resumed log.
  const auto same = [](const std::string& a, const std::string& b) {
    std::error_code ec;
    return std::filesystem::equivalent(a, b, ec);
  };
  if (resumed && resumed->log_beside && !resumed->path.empty() && same(resumed->path, checkpoint) &&
      same(checkpoint_log_path(resumed->path), log_file_.path) &&
      (!resumed->history_beside ||
       same(checkpoint_history_path(resumed->path), history_file_.path)) &&
      log_.compare(0, resumed->log.size(), resumed->log) == 0) {
    log_file_.state = State::Ours;
    log_file_.synced = resumed->log.size();
    log_file_.hash = fnv1a(resumed->log.data(), resumed->log.size());
    history_file_.state = State::Free;
    if (resumed->history_beside) {
      const std::vector<double>& h = resumed->progress.history;
      history_file_.state = State::Ours;
      history_file_.synced = h.size() * sizeof(double);
      history_file_.hash = fnv1a(h.data(), h.size() * sizeof(double));
    }
  }
}

std::pair<std::uint64_t, std::uint64_t> CheckpointLogFile::append() {
  try {
    append(log_file_, log_.data(), log_.size());
  } catch (const UsageError&) {
    history_file_.state = State::Unknown;  // the next save holds both
    throw;
  }
  return {log_file_.pending, log_file_.pending_hash};
}

std::pair<std::uint64_t, std::uint64_t> CheckpointLogFile::append_history(
    const std::vector<double>& history) {
  try {
    append(history_file_, reinterpret_cast<const char*>(history.data()),
           history.size() * sizeof(double));
  } catch (const UsageError&) {
    log_file_.state = State::Unknown;  // the next save holds both
    throw;
  }
  return {history.size(), history_file_.pending_hash};
}

void CheckpointLogFile::append(Stream& s, const char* bytes, std::uint64_t size) {
  if (s.state == State::Free) {
    s.synced = 0;
    s.hash = FNV_BASIS;
  }
  if (size < s.synced) {  // the caller's log shrank: start again from a whole save
    s.state = State::Unknown;
    throw UsageError("cannot write '" + printable(s.path) + "': it is shorter than saved");
  }
  // A file of another run or a link planted there is removed, not followed or appended to: the
  // checkpoint in place holds its own log (State::Free). O_NONBLOCK: a FIFO is not waited on.
  if (s.state == State::Free && ::unlink(s.path.c_str()) != 0 && errno != ENOENT) {
    const int e = errno;
    s.state = State::Unknown;
    cannot_write(s.path, e);
  }
  const int flags = O_WRONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK |
                    (s.state == State::Free ? O_CREAT | O_EXCL : 0);
  const int fd = ::open(s.path.c_str(), flags, 0666);
  struct stat st {};
  int error = fd < 0 ? errno : ::fstat(fd, &st) != 0 ? errno : 0;
  if (!error && !S_ISREG(st.st_mode)) {
    ::close(fd);
    s.state = State::Unknown;
    throw UsageError("cannot write '" + printable(s.path) + "': it is not a regular file");
  }
  // Cut back to what the checkpoint in place records (a save that ended before its rename left
  // more), then the bytes since: the bytes that checkpoint needs are never written over.
  if (!error && ::ftruncate(fd, static_cast<off_t>(s.synced)) != 0) error = errno;
  for (std::uint64_t at = s.synced; !error && at < size;) {
    const ssize_t n = ::pwrite(fd, bytes + at, size - at, static_cast<off_t>(at));
    if (n < 0 && errno != EINTR) error = errno;
    if (n > 0) at += static_cast<std::uint64_t>(n);
  }
  if (fd >= 0 && ::close(fd) != 0 && !error) error = errno;
  if (error) {
    // The checkpoint in place still has its bytes; the next save holds its log itself.
    s.state = State::Unknown;
    // Opened without O_CREAT (appending to the file of this run's earlier saves): ENOENT says the
    // file went, not its folder, which file_error_text would name.
    std::error_code ec;
    const std::filesystem::path folder = std::filesystem::path(s.path).parent_path();
    if (error == ENOENT && !(flags & O_CREAT) &&
        std::filesystem::is_directory(folder.empty() ? "." : folder, ec))
      throw UsageError("cannot write '" + printable(s.path) +
                       "': it was removed since the last save (the next save holds it itself)");
    cannot_write(s.path, error);
  }
  s.pending = size;
  s.pending_hash = fnv1a(bytes + s.synced, size - s.synced, s.hash);
}

void CheckpointLogFile::committed() {
  if (!beside()) {
    // The checkpoint in place holds its log and history: the files beside are no one's now.
    // Removed, so that none is left that no checkpoint goes with; the next save starts them anew.
    for (Stream* s : {&log_file_, &history_file_}) {
      ::unlink(s->path.c_str());
      s->state = State::Free;
    }
    return;
  }
  for (Stream* s : {&log_file_, &history_file_}) {
    s->synced = s->pending;
    s->hash = s->pending_hash;
    s->state = State::Ours;
  }
}

}  // namespace shellcontract
