// Only regular files are written or replaced, and what cannot be written is found before the
// run. Devices need mknod and read-only files a bind mount: as root (CI); elsewhere those tests
// skip and say why. Each failed against the code before the fix as its
// comment says.
#include <sys/file.h>
#include <fcntl.h>

#include "hostile/hostile_support.hpp"

namespace shellcontract {
namespace {

using test::Hostile;
using test::run_cli;

// Before: the rename replaced the device node by a regular file (as root, --log /dev/null would
// have replaced /dev/null).
TEST_F(Hostile, ADeviceGivenAsAnOutputIsNeverReplaced) {
  const fs::path dev = dir_ / "null";
  std::string why;
  if (!make_device(dev, 3, why)) SKIP_OR_FAIL_UNDER_CI(why);
  const auto r = run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "o.off").string(), "-n", "2", "-q", "--log",
                          dev.string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  struct stat st {};
  ASSERT_EQ(::lstat(dev.c_str(), &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode)) << "the device node was replaced";
  EXPECT_FALSE(fs::exists(dir_ / "o.off"));
}

// Before: the same for a FIFO (no root needed).
TEST_F(Hostile, AFifoGivenAsAnOutputIsNeverReplaced) {
  const fs::path fifo = dir_ / "fifo.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0666), 0);
  const auto r = run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "o.off").string(), "-n", "2", "-q",
                          "--summary", fifo.string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  struct stat st {};
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
  // repair and regions refuse it too.
  EXPECT_EQ(run_cli({"repair", test::mesh("ico2.off"), "-o", fifo.string()}).exit_code, 1);
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
}

// Before: `run -o FIFO` (or /dev/null, a folder) was refused for its missing extension, where
// `repair -o` refused it for what it is.
TEST_F(Hostile, ASpecialResultIsRefusedForWhatItIsBeforeItsName) {
  const fs::path fifo = dir_ / "result";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0666), 0);
  fs::create_directories(dir_ / "folder");
  for (const fs::path& out : {fifo, dir_ / "folder"}) {
    const auto r = run_cli({"run", test::mesh("ico2.off"), "-o", out.string(), "-n", "2", "-q"});
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(r.output.find("extension"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(out == fifo ? "not a regular file" : "is a folder"), std::string::npos)
        << r.output;
  }
  struct stat st {};
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
}

// Before: a read-only existing output was found only when its rename failed, after the run
// (the last frame's progress line, then exit 1). A read-only bind mount of the file makes it
// non-writable even for root.
TEST_F(Hostile, ANonWritableExistingOutputIsRefusedBeforeTheRun) {
  const fs::path log = dir_ / "log.csv";
  test::spit(dir_ / "src.csv", "old log\n");
  std::string why;
  if (!bind(dir_ / "src.csv", log, why, /*read_only=*/true)) SKIP_OR_FAIL_UNDER_CI(why);
  const auto r = run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "o.off").string(), "-n", "3", "--log",
                          log.string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output.find("frame 3/3"), std::string::npos) << "found only after the run:\n" << r.output;
  EXPECT_EQ(test::slurp(log), "old log\n");
}

// A read-only folder is found before the run (the probe cannot create a file there).
TEST_F(Hostile, AReadOnlyFolderIsRefusedBeforeTheRun) {
  std::string why;
  if (!mount_tmpfs(dir_ / "ro", 1 << 20, why, /*read_only=*/true)) SKIP_OR_FAIL_UNDER_CI(why);
  const auto r = run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "ro" / "o.off").string(), "-n", "3"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output.find("frame 3/3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("read-only"), std::string::npos) << r.output;
}

// Before: a second run started while a first one wrote into the same export folder mixed their
// frames; now the folder is locked by the run that writes into it.
TEST_F(Hostile, AnExportFolderInUseByAnotherRunIsRefused) {
  fs::create_directories(dir_ / "frames");
  const int fd = ::open((dir_ / "frames").c_str(), O_RDONLY | O_DIRECTORY);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);  // as a running run holds it
  const auto r = run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "o.off").string(), "-n", "4", "-q",
                          "--export-dir", (dir_ / "frames").string()});
  ::close(fd);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(test::listing(dir_ / "frames").empty());
  EXPECT_FALSE(fs::exists(dir_ / "o.off"));
}

}  // namespace
}  // namespace shellcontract
