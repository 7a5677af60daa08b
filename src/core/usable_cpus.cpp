// The cgroup CPU quota and the CPUs this process may use (usable_cpus.hpp). The same reading as
// python/shellcontract/sweep_host.py's, for the sweep's workers.
#include "core/usable_cpus.hpp"

#include <tbb/info.h>

#include <algorithm>
#include <charconv>
#include <climits>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

/// The first line of a small file (its first 256 bytes at most); empty when it cannot be read.
std::string first_line(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  char buffer[256];
  in.read(buffer, sizeof buffer);
  const std::string text(buffer,
                         static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return text.substr(0, text.find('\n'));
}

/// A decimal integer and nothing else but surrounding blanks (locale-free).
bool whole_integer(const std::string& text, long long& value) {
  const char* begin = text.data();
  const char* end = begin + text.size();
  while (begin < end && (*begin == ' ' || *begin == '\t' || *begin == '\r')) ++begin;
  while (end > begin && (end[-1] == ' ' || end[-1] == '\t' || end[-1] == '\r')) --end;
  if (begin == end) return false;
  const std::from_chars_result r = std::from_chars(begin, end, value);
  return r.ec == std::errc() && r.ptr == end;
}

/// ceil(quota / period) CPUs; 0 (no quota) unless both are positive (v1 writes -1 for none).
int cpus_of(long long quota, long long period) {
  if (quota <= 0 || period <= 0) return 0;
  const long long cpus = quota / period + (quota % period != 0 ? 1 : 0);
  return static_cast<int>(std::min<long long>(cpus, INT_MAX));
}

/// cgroup v2: `cpu.max` is "QUOTA PERIOD", or "max PERIOD" for none.
int v2_limit(const fs::path& dir) {
  const std::string line = first_line(dir / "cpu.max");
  const std::size_t space = line.find(' ');
  long long quota = 0, period = 0;
  if (space == std::string::npos || !whole_integer(line.substr(0, space), quota) ||
      !whole_integer(line.substr(space + 1), period))
    return 0;
  return cpus_of(quota, period);
}

/// cgroup v1: the cpu controller's `cpu.cfs_quota_us` (-1 for none) and `cpu.cfs_period_us`.
int v1_limit(const fs::path& dir) {
  long long quota = 0, period = 0;
  if (!whole_integer(first_line(dir / "cpu.cfs_quota_us"), quota) ||
      !whole_integer(first_line(dir / "cpu.cfs_period_us"), period))
    return 0;
  return cpus_of(quota, period);
}

/// The smaller of two limits, 0 being none.
int tighter(int a, int b) {
  if (a <= 0) return b;
  if (b <= 0) return a;
  return std::min(a, b);
}

/// The tightest limit of the cgroup `path` ("/a/b") under the mount `base` and of each ancestor
/// found there, down to `base` itself: a parent's quota holds its children too, and a container
/// whose cgroup is mounted as the root has its own limit there, not under its full path.
template <typename Limit>
int tightest_along(const fs::path& base, const std::string& path, Limit limit_of) {
  std::vector<std::string> parts;
  for (std::size_t start = 0; start <= path.size();) {
    std::size_t end = path.find('/', start);
    if (end == std::string::npos) end = path.size();
    const std::string part = path.substr(start, end - start);
    if (part == "..") return 0;  // not a path the kernel writes: nothing outside the mount is read
    if (!part.empty() && part != ".") parts.push_back(part);
    start = end + 1;
  }
  int best = 0;
  fs::path dir = base;
  std::vector<fs::path> dirs{dir};
  for (const std::string& part : parts) dirs.push_back(dir /= part);
  for (const fs::path& d : dirs) {
    std::error_code error;
    if (fs::is_directory(d, error)) best = tighter(best, limit_of(d));
  }
  return best;
}

bool has_cpu_controller(const std::string& controllers) {
  for (std::size_t start = 0; start <= controllers.size();) {
    std::size_t end = controllers.find(',', start);
    if (end == std::string::npos) end = controllers.size();
    if (controllers.compare(start, end - start, "cpu") == 0) return true;
    start = end + 1;
  }
  return false;
}

}  // namespace

int cgroup_cpu_limit(const std::string& cgroup_root, const std::string& proc_self_cgroup) {
  try {
    int best = 0;
    const fs::path root(cgroup_root);
    for (std::size_t start = 0; start < proc_self_cgroup.size();) {
      std::size_t end = proc_self_cgroup.find('\n', start);
      if (end == std::string::npos) end = proc_self_cgroup.size();
      // "ID:CONTROLLERS:PATH"; the path may itself hold colons.
      const std::string line = proc_self_cgroup.substr(start, end - start);
      start = end + 1;
      const std::size_t c1 = line.find(':');
      const std::size_t c2 = c1 == std::string::npos ? c1 : line.find(':', c1 + 1);
      if (c2 == std::string::npos) continue;
      const std::string id = line.substr(0, c1);
      const std::string controllers = line.substr(c1 + 1, c2 - c1 - 1);
      const std::string path = line.substr(c2 + 1);
      if (path.empty() || path[0] != '/') continue;
      if (id == "0" && controllers.empty()) {  // v2, the unified hierarchy mounted at the root
        best = tighter(best, tightest_along(root, path, v2_limit));
      } else if (controllers.find('/') == std::string::npos && has_cpu_controller(controllers)) {
        // v1: the cpu controller's hierarchy, at root/cpu (a link where it is shared with
        // cpuacct) or at root/<its controllers>, "cpu,cpuacct".
        for (const fs::path& base : {root / "cpu", root / controllers}) {
          std::error_code error;
          if (fs::is_directory(base, error)) {
            best = tighter(best, tightest_along(base, path, v1_limit));
            break;
          }
        }
      }
    }
    return best;
  } catch (const std::exception&) {  // nothing read here is worth failing a run for
    return 0;
  }
}

int usable_cpus() {
  static const int cpus = [] {
    const int affinity = std::max(1, tbb::info::default_concurrency());
    std::ifstream in("/proc/self/cgroup", std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const int quota = cgroup_cpu_limit("/sys/fs/cgroup", text);
    return quota > 0 ? std::min(affinity, quota) : affinity;
  }();
  return cpus;
}

}  // namespace shellcontract
