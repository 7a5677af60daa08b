// Symbolic links and descriptors as outputs (output_target.hpp; docs/design/output-safety.md).
#include "mesh/output_target.hpp"

#include <fcntl.h>
#include <linux/capability.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <string>

#include "mesh/file_safety.hpp"

namespace shellcontract {
namespace {

/// The kernel's own limit on the links of one path (MAXSYMLINKS).
constexpr int MAX_LINKS = 40;

bool all_digits(const std::string& s) {
  return !s.empty() && s.size() < 10 &&
         std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
}

/// Whether `real` (a canonical folder) is this process's descriptor folder: /proc/PID/fd or
/// /proc/PID/task/TID/fd, which /proc/self/fd, /proc/thread-self/fd and /dev/fd resolve to.
bool own_descriptor_folder(const std::string& real) {
  const std::string proc = "/proc/" + std::to_string(::getpid()) + "/";
  if (real.compare(0, proc.size(), proc) != 0) return false;
  const std::string rest = real.substr(proc.size());
  if (rest == "fd") return true;
  const std::string task = "task/";
  if (rest.compare(0, task.size(), task) != 0 || rest.size() < task.size() + 4 ||
      rest.compare(rest.size() - 3, 3, "/fd") != 0)
    return false;
  return all_digits(rest.substr(task.size(), rest.size() - task.size() - 3));
}

std::string folder_of(const std::string& p) {
  const auto slash = p.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? std::string("/") : p.substr(0, slash);
}

std::string name_of(const std::string& p) {
  const auto slash = p.find_last_of('/');
  return slash == std::string::npos ? p : p.substr(slash + 1);
}

bool has_cap_fowner() {
  __user_cap_header_struct header{_LINUX_CAPABILITY_VERSION_3, 0};
  __user_cap_data_struct data[2]{};
  if (::syscall(SYS_capget, &header, data) != 0) return ::geteuid() == 0;
  return (data[CAP_FOWNER / 32].effective & (1u << (CAP_FOWNER % 32))) != 0;
}

}  // namespace

OutputTarget resolve_output(const std::string& path) {
  OutputTarget t;
  t.path = path;
  if (path.empty() || path.find('\0') != std::string::npos) return t;  // the writer says why
  std::string p = path;
  for (int hop = 0; hop <= MAX_LINKS; ++hop) {
    const std::string folder = folder_of(p), name = name_of(p);
    // Before lstat: a descriptor that is not open has no entry there, and is still no file to
    // create (stream_problem says so).
    char real[PATH_MAX];
    if (all_digits(name) && ::realpath(folder.c_str(), real) != nullptr &&
        own_descriptor_folder(real)) {
      t.kind = OutputTarget::Kind::STREAM;
      t.fd = std::atoi(name.c_str());
      return t;
    }
    struct stat link {};
    if (::lstat(p.c_str(), &link) != 0 || !S_ISLNK(link.st_mode)) {
      t.path = p;
      return t;
    }
    // Replacing the target of a link that another user planted in /tmp would let them choose
    // which of the caller's (or root's) files is replaced: the kernel refuses to follow such a
    // link when it opens a path (fs.protected_symlinks), and this manual walk does as well.
    struct stat dir {};
    if (::stat(folder.c_str(), &dir) == 0 && (dir.st_mode & S_ISVTX) && (dir.st_mode & S_IWOTH) &&
        link.st_uid != ::geteuid() && link.st_uid != dir.st_uid) {
      t.problem = "it is a symbolic link of another user (uid " + std::to_string(link.st_uid) +
                  ") in the sticky folder '" + printable(folder) +
                  "': it is neither followed nor replaced";
      t.error = EACCES;
      return t;
    }
    std::string target(PATH_MAX, '\0');
    const ssize_t n = ::readlink(p.c_str(), target.data(), target.size());
    if (n < 0 || static_cast<std::size_t>(n) >= target.size()) {
      t.path = p;  // vanished meanwhile: the writer meets what is there now
      return t;
    }
    target.resize(static_cast<std::size_t>(n));
    p = !target.empty() && target[0] == '/' ? target : folder + "/" + target;
  }
  t.problem = "too many symbolic links (a loop?)";
  t.error = ELOOP;
  return t;
}

std::string replaced_file(const std::string& path) {
  const OutputTarget t = resolve_output(path);
  return t.kind == OutputTarget::Kind::FILE && t.problem.empty() && !t.path.empty() ? t.path : path;
}

std::string stream_problem(int fd, int& error_number) {
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags < 0) {
    error_number = errno;
    return "it names the descriptor " + std::to_string(fd) + ", which is not open";
  }
  if ((flags & O_ACCMODE) == O_RDONLY) {
    error_number = EBADF;
    return "it names the descriptor " + std::to_string(fd) + ", which is open for reading only";
  }
  return {};
}

std::string sticky_problem(const struct stat& st, const struct stat& folder) {
  if (!(folder.st_mode & S_ISVTX)) return {};
  const uid_t me = ::geteuid();
  if (st.st_uid == me || folder.st_uid == me || has_cap_fowner()) return {};
  return "exists and cannot be replaced: it belongs to another user (uid " +
         std::to_string(st.st_uid) +
         ") and its folder is sticky (like /tmp: only the file's owner, the folder's owner or "
         "root may replace or remove a file there); remove it as its owner, or choose another "
         "name";
}

}  // namespace shellcontract
