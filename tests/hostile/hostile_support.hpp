// What the hostile-use tests share (docs/design/output-safety.md): a fresh folder per
// test, the CLI, file bytes, and the root-only tools (mknod, tmpfs, bind mounts) with a skip
// that says why where the machine cannot do them, which is a failure under
// SHELLCONTRACT_STRICT_TESTS=1 (.ci/run; support/ci_skip.hpp: CI runs as root).
#pragma once

#include <gtest/gtest.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/ci_skip.hpp"
#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace fs = std::filesystem;
}

namespace shellcontract::test {

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void spit(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary);
  out << bytes;
}

inline std::string mesh(const char* name) { return std::string(MESH_DIR) + "/" + name; }

/// Names in a folder (sorted), hidden ones too: what a refused run must not have left.
inline std::vector<std::string> listing(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

/// A fresh folder per test under the system's temporary folder; mounts made by the test are
/// undone first at the end.
class Hostile : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(SHELLCONTRACT_CLI_PATH))
      SKIP_OR_FAIL_UNDER_CI(SHELLCONTRACT_CLI_PATH << " not built");
    dir_ = fs::temp_directory_path() /
           ("shellcontract_hostile_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    for (auto it = mounts_.rbegin(); it != mounts_.rend(); ++it) ::umount2(it->c_str(), MNT_DETACH);
    std::error_code ec;
    fs::remove_all(dir_, ec);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    for (auto it = mounts_.rbegin(); it != mounts_.rend(); ++it) ::umount2(it->c_str(), MNT_DETACH);
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  /// Mounts a tmpfs of `bytes` at `at` (created); false (with `why`) if the machine cannot.
  bool mount_tmpfs(const fs::path& at, std::size_t bytes, std::string& why, bool read_only = false) {
    fs::create_directories(at);
    const std::string opts = "size=" + std::to_string(bytes);
    if (::mount("tmpfs", at.c_str(), "tmpfs", read_only ? MS_RDONLY : 0, opts.c_str()) != 0) {
      why = "cannot mount a tmpfs (" + std::string(std::strerror(errno)) + "; needs root / CAP_SYS_ADMIN)";
      return false;
    }
    mounts_.push_back(at.string());
    return true;
  }
  /// Bind-mounts `from` at `at` (created as a folder or a file like `from`); read-only if asked.
  bool bind(const fs::path& from, const fs::path& at, std::string& why, bool read_only = false) {
    if (fs::is_directory(from)) fs::create_directories(at);
    else if (!fs::exists(at)) spit(at, "");
    if (::mount(from.c_str(), at.c_str(), nullptr, MS_BIND, nullptr) != 0) {
      why = "cannot bind-mount (" + std::string(std::strerror(errno)) + "; needs root / CAP_SYS_ADMIN)";
      return false;
    }
    mounts_.push_back(at.string());
    if (read_only &&
        ::mount(nullptr, at.c_str(), nullptr, MS_REMOUNT | MS_BIND | MS_RDONLY, nullptr) != 0) {
      why = "cannot remount read-only (" + std::string(std::strerror(errno)) + ")";
      return false;
    }
    return true;
  }
  /// Makes a character device like /dev/null (1, 3) or /dev/zero (1, 5) at `at`.
  bool make_device(const fs::path& at, unsigned minor, std::string& why) {
    if (::mknod(at.c_str(), S_IFCHR | 0666, makedev(1, minor)) != 0) {
      why = "cannot mknod (" + std::string(std::strerror(errno)) + "; needs root / CAP_MKNOD)";
      return false;
    }
    return true;
  }

  fs::path dir_;
  std::vector<std::string> mounts_;
};

}  // namespace shellcontract::test
