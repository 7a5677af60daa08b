// The caller's side of saving a checkpoint (shellcontract/checkpoint.hpp), and the caller's log
// kept beside the checkpoint (CheckpointLogFile): a log written whole into every save made each
// save as large as the run so far, so a long run spent the square of its frames on saving.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <memory>

#include "mesh/file_safety.hpp"
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

std::string checkpoint_log_path(const std::string& checkpoint) { return checkpoint + ".log"; }

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
    const LogBeside beside{size, hash};
    write_checkpoint(path, c, &beside);
  } else {
    c.log = log.log();  // the whole log, once: see CheckpointLogFile
    write_checkpoint(path, c);
  }
  log.committed();
}

std::string read_log_beside(const std::string& path, const LogBeside& beside) {
  const std::string file = checkpoint_log_path(path);
  const std::string start = "checkpoint " + printable(path) + ": its log ";
  const std::string why =
      " (the checkpoint keeps the run's log in that file beside it: move or copy the two "
      "together)";
  std::string bytes;
  try {
    bytes = read_regular_file(file);
  } catch (const InputError& e) {
    rethrow_input_error_as(e, start + e.what() + why);  // errno and path kept
  }
  if (bytes.size() < beside.size)
    throw InputError(start + printable(file) + " holds " + std::to_string(bytes.size()) +
                     " bytes, fewer than the " + std::to_string(beside.size) +
                     " the checkpoint was saved with (truncated, or another run's log)" + why);
  // Bytes past the recorded length are a later save's that ended before its checkpoint was
  // renamed into place: not this checkpoint's.
  bytes.resize(static_cast<std::size_t>(beside.size));
  if (fnv1a(bytes.data(), bytes.size()) != beside.hash)
    throw InputError(start + printable(file) +
                     " is not the one the checkpoint was saved with (damaged, or another run's "
                     "log)" +
                     why);
  return bytes;
}

CheckpointLogFile::CheckpointLogFile(const std::string& checkpoint, const std::string& log,
                                     const Checkpoint* resumed)
    : path_(checkpoint_log_path(checkpoint)), log_(log) {
  std::error_code ec;
  // Resumed from this very file with its log beside: the log goes on there, after the length
  // the checkpoint records. Otherwise the file beside may be what the checkpoint in place needs
  // (another run's, the one resumed from when that is format 4 elsewhere): left alone.
  if (resumed && resumed->log_beside && !resumed->path.empty() &&
      std::filesystem::equivalent(resumed->path, checkpoint, ec) &&
      log_.compare(0, resumed->log.size(), resumed->log) == 0) {
    state_ = State::Ours;
    synced_ = resumed->log.size();
    hash_ = fnv1a(resumed->log.data(), resumed->log.size());
  }
}

std::pair<std::uint64_t, std::uint64_t> CheckpointLogFile::append() {
  if (state_ == State::Free) {
    synced_ = 0;
    hash_ = FNV_BASIS;
  }
  if (log_.size() < synced_) {  // the caller's log shrank: start again from a whole save
    state_ = State::Unknown;
    throw UsageError("cannot write '" + printable(path_) + "': the log is shorter than saved");
  }
  // A file of another run or a link planted there is removed, not followed or appended to: the
  // checkpoint in place holds its own log (State::Free). O_NONBLOCK: a FIFO is not waited on.
  if (state_ == State::Free && ::unlink(path_.c_str()) != 0 && errno != ENOENT) {
    const int e = errno;
    state_ = State::Unknown;
    cannot_write(path_, e);
  }
  const int flags = O_WRONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK |
                    (state_ == State::Free ? O_CREAT | O_EXCL : 0);
  const int fd = ::open(path_.c_str(), flags, 0666);
  struct stat st {};
  int error = fd < 0 ? errno : ::fstat(fd, &st) != 0 ? errno : 0;
  if (!error && !S_ISREG(st.st_mode)) {
    ::close(fd);
    state_ = State::Unknown;
    throw UsageError("cannot write '" + printable(path_) + "': it is not a regular file");
  }
  // Cut back to what the checkpoint in place records (a save that ended before its rename left
  // more), then the lines since: the bytes that checkpoint needs are never written over.
  if (!error && ::ftruncate(fd, static_cast<off_t>(synced_)) != 0) error = errno;
  for (std::uint64_t at = synced_; !error && at < log_.size();) {
    const ssize_t n = ::pwrite(fd, log_.data() + at, log_.size() - at, static_cast<off_t>(at));
    if (n < 0 && errno != EINTR) error = errno;
    if (n > 0) at += static_cast<std::uint64_t>(n);
  }
  if (fd >= 0 && ::close(fd) != 0 && !error) error = errno;
  if (error) {
    // The checkpoint in place still has its bytes; the next save holds its log itself.
    state_ = State::Unknown;
    cannot_write(path_, error);
  }
  pending_ = log_.size();
  pending_hash_ = fnv1a(log_.data() + synced_, log_.size() - synced_, hash_);
  return {pending_, pending_hash_};
}

void CheckpointLogFile::committed() {
  if (state_ == State::Unknown) {
    // The checkpoint in place holds its log: the file beside is no one's now. Removed, so that
    // none is left that no checkpoint goes with; the next save starts it anew.
    ::unlink(path_.c_str());
    state_ = State::Free;
    return;
  }
  synced_ = pending_;
  hash_ = pending_hash_;
  state_ = State::Ours;
}

}  // namespace shellcontract
