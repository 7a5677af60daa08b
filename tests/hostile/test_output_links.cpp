// Outputs through symbolic links and descriptors, in sticky folders, of other users, in deep
// folders (docs/design/output-safety.md, "Symbolic links and streams", "Sticky folders and
// owners"). Each failed against the code before the fix as its comment says; the links are the
// test's own (never the machine's /dev/stderr, which the old code replaced as root).
#include <sys/wait.h>
#include <unistd.h>

#include "hostile/hostile_support.hpp"
#include "shellcontract/file_error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/output_files.hpp"

namespace shellcontract {
namespace {

using test::Hostile;
using test::run_cli;

bool is_link(const fs::path& p) {
  struct stat st {};
  return ::lstat(p.c_str(), &st) == 0 && S_ISLNK(st.st_mode);
}

// Before: the rename replaced the link by a plain file, its target left with the old log.
TEST_F(Hostile, ALinkGivenAsAnOutputIsFollowedAndKept) {
  fs::create_directories(dir_ / "real");
  test::spit(dir_ / "real" / "log.csv", "old log\n");
  fs::create_symlink(dir_ / "real" / "log.csv", dir_ / "log.csv");
  fs::create_symlink("real/new.json", dir_ / "summary.json");  // relative, its target missing
  const auto r = run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "o.off").string(), "-n", "2",
                          "-q", "--log", (dir_ / "log.csv").string(), "--summary",
                          (dir_ / "summary.json").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(is_link(dir_ / "log.csv"));
  EXPECT_TRUE(is_link(dir_ / "summary.json"));
  EXPECT_EQ(test::slurp(dir_ / "real" / "log.csv").rfind("frame,", 0), 0u);
  EXPECT_NE(test::slurp(dir_ / "real" / "new.json").find("\"status\""), std::string::npos);
  // Nothing else was made beside the links or the targets (no temporary left).
  EXPECT_EQ(test::listing(dir_ / "real"), (std::vector<std::string>{"log.csv", "new.json"}));
}

// Before: `--log /dev/stderr 2>err.txt` (here the test's own link to /proc/self/fd/2) passed the
// check, for the link resolved to a regular file, and was replaced by a plain file: the log not in
// err.txt, exit 0. Now the descriptor is written into at its own offset, after what came before.
TEST_F(Hostile, ALinkToARedirectedDescriptorIsWrittenIntoNeverReplaced) {
  fs::create_symlink("/proc/self/fd/2", dir_ / "stderr");
  fs::create_symlink("/proc/self/fd/1", dir_ / "stdout");
  const fs::path err = dir_ / "err.txt", out = dir_ / "out.txt";
  test::spit(err, "before\n");
  const auto r = test::run_command(
      test::cli_line({"run", test::mesh("ico2.off"), "-o", (dir_ / "o.off").string(), "-n", "2",
                      "-q", "--log", (dir_ / "stderr").string(), "--summary",
                      (dir_ / "stdout").string()}) +
      " 2>>" + test::quoted(err.string()) + " >" + test::quoted(out.string()) + "; echo $?");
  EXPECT_EQ(r.output, "0\n");
  EXPECT_TRUE(is_link(dir_ / "stderr"));
  EXPECT_TRUE(is_link(dir_ / "stdout"));
  EXPECT_EQ(test::slurp(err).rfind("before\nframe,", 0), 0u) << test::slurp(err);
  EXPECT_NE(test::slurp(out).find("\"status\""), std::string::npos) << test::slurp(out);
}

// Before: a checkpoint "saved" into standard output (a file here) replaced the link, and its log
// beside it would go into the link's folder (/dev as root). A checkpoint must be a file to resume.
TEST_F(Hostile, ACheckpointIntoADescriptorIsRefused) {
  fs::create_symlink("/proc/self/fd/1", dir_ / "stdout");
  const auto r = test::run_command(
      test::cli_line({"run", test::mesh("ico2.off"), "-o", (dir_ / "o.off").string(), "-n", "2",
                      "-q", "--checkpoint", (dir_ / "stdout").string()}) +
      " 2>&1 >" + test::quoted((dir_ / "out.txt").string()));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("a checkpoint must be a file"), std::string::npos) << r.output;
  EXPECT_TRUE(is_link(dir_ / "stdout"));
  EXPECT_FALSE(fs::exists(dir_ / "o.off"));
}

/// The uid and gid of nobody (65534), whose files the root-only tests make.
constexpr uid_t NOBODY = 65534;

// A link planted by another user in a sticky, world-writable folder (/tmp) is not followed, as the
// kernel's fs.protected_symlinks would not when opening it: following it would let that user pick
// which of root's files is replaced. Before, root replaced the link itself (no harm then); a
// follow without this rule would have replaced the victim.
TEST_F(Hostile, AnotherUsersLinkInAStickyFolderIsNotFollowed) {
  if (::geteuid() != 0) SKIP_OR_FAIL_UNDER_CI("needs root to make a link of another user");
  const fs::path sticky = dir_ / "tmp", victim = dir_ / "victim.txt", link = sticky / "log.csv";
  fs::create_directories(sticky);
  ::chmod(sticky.c_str(), 01777);
  test::spit(victim, "precious");
  fs::create_symlink(victim, link);
  ASSERT_EQ(::lchown(link.c_str(), NOBODY, NOBODY), 0);
  const auto r = run_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "o.off").string(), "-n", "2",
                          "-q", "--log", link.string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("sticky"), std::string::npos) << r.output;
  EXPECT_EQ(test::slurp(victim), "precious");
  EXPECT_TRUE(is_link(link));
}

// Before: a writable file of another user in a sticky folder passed the check, and the rename
// that replaces it failed after the run ("permission denied", the result lost). The check runs
// as nobody in a child; its exit status says what it did (0: refused as the sticky rule says).
TEST_F(Hostile, AnotherUsersFileInAStickyFolderIsRefusedBeforeTheRun) {
  if (::geteuid() != 0) SKIP_OR_FAIL_UNDER_CI("needs root to make files of two other users");
  const fs::path sticky = dir_ / "scratch", shared = sticky / "shared.off";
  fs::create_directories(sticky);
  ::chmod(sticky.c_str(), 01777);
  test::spit(shared, "old\n");
  ::chmod(shared.c_str(), 0666);
  ASSERT_EQ(::chown(shared.c_str(), 1, 1), 0);  // daemon's, not the checking user's
  const pid_t child = ::fork();
  if (child == 0) {
    if (::setgid(NOBODY) != 0 || ::setuid(NOBODY) != 0) ::_exit(3);
    try {
      check_output_files({{"-o", shared.string()}}, {});
      ::_exit(1);  // accepted: the run would lose its result at the end
    } catch (const OutputFileError& e) {
      ::_exit(e.error_number() == EPERM && std::string(e.what()).find("sticky") != std::string::npos
                  ? 0
                  : 2);
    } catch (...) {
      ::_exit(2);
    }
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "1: accepted, 2: refused for another reason, 3: no setuid";
  EXPECT_EQ(test::slurp(shared), "old\n");
}

// Before: root replacing a user's 0640 result made it root's, and the user could no longer read it.
TEST_F(Hostile, AReplacedFileKeepsItsOwnerAndGroup) {
  if (::geteuid() != 0) SKIP_OR_FAIL_UNDER_CI("needs root to give a file to another user");
  const fs::path f = dir_ / "own.txt";
  test::spit(f, "old\n");
  ASSERT_EQ(::chown(f.c_str(), NOBODY, NOBODY), 0);
  ::chmod(f.c_str(), 0640);
  write_text_atomic(f.string(), "new\n");
  struct stat st {};
  ASSERT_EQ(::stat(f.c_str(), &st), 0);
  EXPECT_EQ(st.st_uid, NOBODY);
  EXPECT_EQ(st.st_gid, NOBODY);
  EXPECT_EQ(st.st_mode & 07777, 0640u);
  EXPECT_EQ(test::slurp(f), "new\n");
}

/// A folder under `base` whose path has exactly `length` bytes.
fs::path deep_folder(const fs::path& base, std::size_t length) {
  std::string p = base.string();
  while (p.size() + 201 < length) p += "/" + std::string(200, 'd');
  p += "/" + std::string(length - p.size() - 1, 'e');
  fs::create_directories(p);
  return p;
}

// Before: the probe was padded to 60 characters, so a folder of about 4035 bytes or more was
// refused for "the file name is too long (7 characters)", though the output and its temporary
// fit in PATH_MAX. Now only a path that does not fit is refused, naming PATH_MAX.
TEST_F(Hostile, ADeepFolderIsRefusedOnlyPastPathMaxAndSaysSo) {
  const fs::path deep = deep_folder(dir_, 4040);
  EXPECT_NO_THROW(check_output_files({{"-o", (deep / "out.off").string()}}, {}));
  const fs::path deeper = deep_folder(dir_, 4085);
  try {
    check_output_files({{"-o", (deeper / "out.off").string()}}, {});
    ADD_FAILURE() << "a path over PATH_MAX was accepted";
  } catch (const OutputFileError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("PATH_MAX"), std::string::npos) << what;
    EXPECT_EQ(what.find("file name is too long"), std::string::npos) << what;
  }
  EXPECT_EQ(test::listing(deep), std::vector<std::string>{});
}

}  // namespace
}  // namespace shellcontract
