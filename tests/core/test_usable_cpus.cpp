// The CPUs a process may use (core/usable_cpus.hpp): its affinity held to its cgroup's CPU
// quota, read from a cgroup tree made here (v2 cpu.max, v1 cfs_quota_us/cfs_period_us, "max",
// nested cgroups, garbage). Before, the default thread count was TBB's, the affinity's alone: a
// container given 2 CPUs of a 64-core host ran 64 threads.
#include <gtest/gtest.h>
#include <tbb/info.h>
#include <unistd.h>

#include <algorithm>
#include <climits>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "core/arena_threads.hpp"
#include "core/usable_cpus.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

class CgroupTree : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("usable_cpus_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }
  /// Writes `text` to root/relative, making its folders.
  void write(const std::string& relative, const std::string& text) {
    const fs::path path = root_ / relative;
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << text;
  }
  int limit(const std::string& proc_self_cgroup) const {
    return cgroup_cpu_limit(root_.string(), proc_self_cgroup);
  }
  fs::path root_;
};

TEST_F(CgroupTree, V2QuotaIsRoundedUpToWholeCpus) {
  write("job/cpu.max", "200000 100000\n");  // docker --cpus=2
  EXPECT_EQ(limit("0::/job\n"), 2);
  write("job/cpu.max", "150000 100000\n");  // --cpus=1.5: two threads, each busy part of the time
  EXPECT_EQ(limit("0::/job\n"), 2);
  write("job/cpu.max", "50000 100000\n");
  EXPECT_EQ(limit("0::/job\n"), 1);
  write("job/cpu.max", "9223372036854775807 1\n");
  EXPECT_EQ(limit("0::/job\n"), INT_MAX);
}

TEST_F(CgroupTree, MaxOrNoFileIsNoQuota) {
  write("job/cpu.max", "max 100000\n");
  EXPECT_EQ(limit("0::/job\n"), 0);
  EXPECT_EQ(limit("0::/elsewhere\n"), 0);  // neither it nor the root has a cpu.max
  EXPECT_EQ(cgroup_cpu_limit((root_ / "absent").string(), "0::/job\n"), 0);
  write("cpu/cpu.cfs_quota_us", "-1\n");
  write("cpu/cpu.cfs_period_us", "100000\n");
  EXPECT_EQ(limit("3:cpu:/\n"), 0);
}

TEST_F(CgroupTree, NestedCgroupsTakeTheTightestAncestor) {
  write("user.slice/cpu.max", "300000 100000\n");
  write("user.slice/session/cpu.max", "max 100000\n");
  write("user.slice/session/job/cpu.max", "800000 100000\n");
  EXPECT_EQ(limit("0::/user.slice/session/job\n"), 3);
  write("user.slice/session/job/cpu.max", "100000 100000\n");
  EXPECT_EQ(limit("0::/user.slice/session/job\n"), 1);
  // A container whose own cgroup is mounted as the root: its full path is not there.
  write("cpu.max", "400000 100000\n");
  EXPECT_EQ(limit("0::/system.slice/docker-0123.scope\n"), 4);
  EXPECT_EQ(limit("0::/\n"), 4);
}

TEST_F(CgroupTree, V1QuotaOfTheCpuControllersHierarchy) {
  write("cpu,cpuacct/docker/abc/cpu.cfs_quota_us", "250000\n");
  write("cpu,cpuacct/docker/abc/cpu.cfs_period_us", "100000\n");
  const std::string text =
      "12:memory:/docker/abc\n"
      "4:cpu,cpuacct:/docker/abc\n"
      "1:name=systemd:/docker/abc\n"
      "0::/docker/abc\n";
  EXPECT_EQ(limit(text), 3);
  // Mounted as root/cpu (Debian's layout, or a link to cpu,cpuacct): that one is read.
  write("cpu/docker/abc/cpu.cfs_quota_us", "100000\n");
  write("cpu/docker/abc/cpu.cfs_period_us", "100000\n");
  EXPECT_EQ(limit(text), 1);
  // cpuacct alone is not the cpu controller.
  EXPECT_EQ(limit("5:cpuacct:/docker/abc\n"), 0);
}

TEST_F(CgroupTree, BothHierarchiesGiveTheSmaller) {
  write("cpu.max", "500000 100000\n");
  write("cpu/cpu.cfs_quota_us", "200000\n");
  write("cpu/cpu.cfs_period_us", "100000\n");
  EXPECT_EQ(limit("0::/\n3:cpu:/\n"), 2);
  EXPECT_EQ(limit("0::/\n"), 5);
}

TEST_F(CgroupTree, GarbageIsNoQuotaNotACrash) {
  for (const char* text : {"", "abc", "100000", "-5 100000", "1e5 100000", "200000 0",
                           "200000 100000 7", "99999999999999999999 100000", " \n",
                           "\xff\xfe\x00\x01", "200000\t100000", "0x30000 100000"}) {
    write("job/cpu.max", text);
    EXPECT_EQ(limit("0::/job\n"), 0) << "cpu.max: " << text;
  }
  fs::remove(root_ / "job" / "cpu.max");
  fs::create_directories(root_ / "job" / "cpu.max");  // a folder where the file should be
  EXPECT_EQ(limit("0::/job\n"), 0);
  write("cpu/cpu.cfs_quota_us", "lots\n");
  write("cpu/cpu.cfs_period_us", "100000\n");
  EXPECT_EQ(limit("2:cpu:/\n"), 0);
  write("cpu.max", "200000 100000\n");  // what a path out of the tree would be compared with
  EXPECT_EQ(limit("0::/job\n"), 2);
  for (const char* text :
       {"", "junk", "0::relative", ":::", "0:", "0::/../..", "2:cpu/../..:/", "\n\n\n"})
    EXPECT_EQ(limit(text), 0) << text;
}

// The process's own: the default thread count follows it. Under a CPU quota (run this test
// binary in a cgroup with cpu.max or cfs_quota_us set) this is what the quota allows.
TEST(UsableCpus, TheDefaultArenaIsThisProcesssUsableCpus) {
  std::ifstream in("/proc/self/cgroup", std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const int affinity = tbb::info::default_concurrency();
  const int quota = cgroup_cpu_limit("/sys/fs/cgroup", text);
  EXPECT_EQ(usable_cpus(), quota > 0 ? std::min(affinity, quota) : affinity);
  EXPECT_EQ(arena_threads(0), usable_cpus());
  EXPECT_EQ(ArenaLease(0).arena().max_concurrency(), usable_cpus());
  // A count given is held to them too.
  EXPECT_EQ(arena_threads(usable_cpus() + 3), usable_cpus());
  EXPECT_EQ(arena_threads(1), 1);
}

}  // namespace
}  // namespace shellcontract
