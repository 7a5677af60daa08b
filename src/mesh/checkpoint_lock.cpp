#include "shellcontract/checkpoint_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>

#include "mesh/file_safety.hpp"
#include "mesh/output_check.hpp"
#include "sim/checkpoint.hpp"

namespace shellcontract {

namespace fs = std::filesystem;

std::string checkpoint_lock_path(const std::string& checkpoint) {
  const fs::path p(checkpoint);
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
                (saves && option.find("resume") == std::string::npos
                     ? ", or choose another " + option
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

CheckpointLocks lock_run_checkpoints(const std::string& checkpoint, const std::string& resume,
                                     bool saves_to_resumed, OptionSpelling spelling) {
  const bool cli = spelling == OptionSpelling::Cli;
  const std::string checkpoint_option = cli ? "--checkpoint" : "checkpoint";
  const std::string resume_option = cli ? "--resume" : "resume";
  CheckpointLocks locks;
  if (!checkpoint.empty())
    locks.saved = lock_checkpoint(checkpoint, saves_to_resumed ? resume_option : checkpoint_option,
                                  true, locks.warnings);
  std::error_code ec;
  if (!resume.empty() && (checkpoint.empty() || !fs::equivalent(resume, checkpoint, ec)))
    locks.resumed = lock_checkpoint(resume, resume_option, false, locks.warnings);
  return locks;
}

}  // namespace shellcontract
