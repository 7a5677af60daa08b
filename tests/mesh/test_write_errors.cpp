// write_file_atomic when the disk refuses the bytes (mesh_io.hpp): the call fails with the
// file system's reason, the old file is kept, and no temporary is left in the folder. A full
// disk is made with RLIMIT_FSIZE (writes past it fail with EFBIG once SIGXFSZ is ignored), in a
// forked child so that the limit does not reach this process's other files; the child reports
// through its exit status. A writer that throws is tested in test_io.cpp; this is the other way
// a write ends early, where the error comes from the stream and not from the caller.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "shellcontract/file_error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(WriteFileAtomic, AFullDiskKeepsTheOldFileAndLeavesNoTemporary) {
  const fs::path dir =
      fs::temp_directory_path() / ("shellcontract_write_errors_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path target = dir / "result.off";
  std::ofstream(target) << "old\n";

  // Exit status of the child: 0 the call failed with EFBIG as an OutputFileError, 1 it returned,
  // 2 another exception, 3 another errno.
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{4096, 4096};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    int status = 1;
    try {
      write_file_atomic(target.string(),
                        [](std::ostream& out) { out << std::string(1 << 16, 'x'); });
    } catch (const OutputFileError& e) {
      status = e.error_number() == EFBIG ? 0 : 3;
    } catch (...) {
      status = 2;
    }
    std::_Exit(status);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "1: the write succeeded past the limit, 2/3: not EFBIG";
  EXPECT_EQ(slurp(target), "old\n");
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"result.off"}) << "a temporary file was left behind";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace shellcontract
