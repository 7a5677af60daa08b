#include "shellcontract/checkpoint_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <filesystem>

#include "mesh/file_safety.hpp"
#include "mesh/output_check.hpp"
#include "mesh/output_target.hpp"
#include "shellcontract/file_error.hpp"
#include "sim/checkpoint.hpp"

namespace shellcontract {

namespace fs = std::filesystem;

std::string checkpoint_lock_path(const std::string& checkpoint) {
  // Beside the file a save replaces (a link's target): two runs naming one checkpoint, one of
  // them through a link, take one lock.
  const fs::path p(replaced_file(checkpoint));
  const std::string name = p.filename().string();
  std::string lock = "." + name + ".lock";
  // A name near the file system's limit of 255 bytes: cut, and told apart from other names
  // with the same beginning by a hash of the whole name.
  if (lock.size() > 255) {
    char hash[17];
    std::snprintf(hash, sizeof hash, "%016llx",
                  static_cast<unsigned long long>(fnv1a(name.data(), name.size())));
    lock = "." + name.substr(0, 200) + "." + hash + ".lock";
  }
  return (p.parent_path() / lock).string();
}

CheckpointLock::~CheckpointLock() {
  ::unlink(path_.c_str());  // while locked: no second run takes this file in between
  if (slot_ >= 0) unregister_temporary(slot_);
  ::close(fd_);  // closing releases the lock
}

bool CheckpointLock::locks(const std::string& checkpoint) const {
  struct stat held {
  }, named{};
  return ::fstat(fd_, &held) == 0 &&
         ::stat(checkpoint_lock_path(checkpoint).c_str(), &named) == 0 && same_inode(held, named);
}

bool CheckpointLock::writable() const {
  const int flags = ::fcntl(fd_, F_GETFL);
  return flags >= 0 && (flags & O_ACCMODE) == O_RDWR;
}

std::unique_ptr<CheckpointLock> lock_checkpoint(const std::string& checkpoint,
                                                const std::string& option, bool saves,
                                                std::vector<std::string>& warnings) {
  const std::string lock = checkpoint_lock_path(checkpoint);
  // A lock file removed by the run that held it, between this run's open and its flock, is
  // locked in vain: taken again, until the file locked is the one under the name.
  for (int attempt = 0; attempt < 100; ++attempt) {
    int fd = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0666);
    if (fd < 0 && !saves && (errno == EACCES || errno == EPERM || errno == EROFS)) {
      // A checkpoint only resumed from, in a folder this run cannot write (a read-only copy):
      // it resumes, as before the lock; a run saving there holds a lock file, readable here.
      fd = ::open(lock.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
      if (fd < 0 && errno == ENOENT) return nullptr;
    }
    if (fd < 0) {
      const int e = errno;
      refuse_file(
          option, checkpoint,
          "cannot make its lock file " + quoted_path(lock) + " (" + file_error_text(e) + ")", e);
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int e = errno;
      ::close(fd);
      if (e == EWOULDBLOCK)
        refuse_file(
            option, checkpoint,
            "another shellcontract run is saving to this checkpoint or resuming from it (it "
            "holds " +
                quoted_path(lock) +
                "); two runs with one checkpoint would resume into each other's state: wait "
                "for it to end" +
                (option.find("resume") == std::string::npos ? ", or choose another " + option
                                                            : std::string()),
            EWOULDBLOCK);  // what flock said: the lock would block (Python's BlockingIOError)
      warnings.push_back(option + ' ' + quoted_path(checkpoint) +
                         ": the file system takes no lock (" + file_error_text(e) +
                         "): a second run with this checkpoint would not be refused");
      ::unlink(lock.c_str());
      return nullptr;
    }
    struct stat held {
    }, named{};
    if (::fstat(fd, &held) == 0 && ::stat(lock.c_str(), &named) == 0 && same_inode(held, named))
      return std::make_unique<CheckpointLock>(fd, lock, register_temporary(lock));
    ::close(fd);
  }
  refuse_file(option, checkpoint,
              "cannot take its lock file " + quoted_path(lock) + " (it keeps being replaced)");
}

CheckpointLocks lock_resumed_checkpoint(const std::string& resume, const std::string& checkpoint,
                                        OptionSpelling spelling) {
  const bool cli = spelling == OptionSpelling::Cli;
  CheckpointLocks locks;
  std::error_code ec;
  // Not a file (missing, a folder): the read says why (exit code 2), as before; no lock file is
  // made for it. A checkpoint in place is never removed by a save, only replaced.
  if (resume.empty() || !fs::is_regular_file(resume, ec)) return locks;
  // Named as lock_run_checkpoints will name it: with checkpoint= on the same lock file, as the
  // checkpoint saved to (its refusal suggests another one).
  const auto folder = [](const std::string& file) {
    const fs::path parent = fs::path(file).parent_path();
    return parent.empty() ? fs::path(".") : parent;
  };
  const bool saved_here = !checkpoint.empty() && fs::equivalent(resume, checkpoint, ec) &&
                          fs::path(resume).filename() == fs::path(checkpoint).filename() &&
                          fs::equivalent(folder(resume), folder(checkpoint), ec);
  const std::string option =
      saved_here ? (cli ? "--checkpoint" : "checkpoint") : (cli ? "--resume" : "resume");
  try {
    // As a checkpoint only resumed from: in a folder this run cannot write (a read-only copy
    // that another user's run saves to), the lock file there is locked read-only.
    locks.resumed = lock_checkpoint(resume, option, false, locks.warnings);
  } catch (const OutputFileError& e) {
    if (e.error_number() == EWOULDBLOCK) throw;
  } catch (const UsageError&) {
  }
  return locks;
}

CheckpointLocks lock_run_checkpoints(const std::string& checkpoint, const std::string& resume,
                                     bool saves_to_resumed, OptionSpelling spelling,
                                     CheckpointLocks held) {
  const bool cli = spelling == OptionSpelling::Cli;
  const std::string checkpoint_option = cli ? "--checkpoint" : "checkpoint";
  const std::string resume_option = cli ? "--resume" : "resume";
  CheckpointLocks locks;
  locks.warnings = std::move(held.warnings);
  std::unique_ptr<CheckpointLock> read_under = std::move(held.resumed);
  if (!checkpoint.empty()) {
    const bool same = read_under && read_under->locks(checkpoint);
    if (same && read_under->writable()) {
      locks.saved = std::move(read_under);
    } else {
      // Locked read-only, it is taken again to save there, refused as before if it cannot be.
      if (same) read_under.reset();
      locks.saved = lock_checkpoint(
          checkpoint, saves_to_resumed ? resume_option : checkpoint_option, true, locks.warnings);
    }
  }
  std::error_code ec;
  if (read_under)  // the file resumed from, read under its lock: held to the end
    locks.resumed = std::move(read_under);
  else if (!resume.empty() && (checkpoint.empty() || !fs::equivalent(resume, checkpoint, ec)))
    locks.resumed = lock_checkpoint(resume, resume_option, false, locks.warnings);
  // A file system that takes no locks, met before the read and again here: said once.
  std::vector<std::string> once;
  for (std::string& w : locks.warnings)
    if (std::find(once.begin(), once.end(), w) == once.end()) once.push_back(std::move(w));
  locks.warnings = std::move(once);
  return locks;
}

}  // namespace shellcontract
