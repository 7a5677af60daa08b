// check_output_files and a write-protected output (docs/design/output-safety.md): a regular
// file with no write permission bit at all (mode 0444, `chmod a-w`) is refused for every user.
// Before, the check was access(W_OK) alone, which always succeeds for root: as root (farm
// containers often run so) a write-protected result was replaced. The rule is on the mode bits,
// so the test holds for any user; it failed on the old code when run as root.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "shellcontract/error.hpp"
#include "shellcontract/output_files.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

class OutputCheck : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("shellcontract_output_check_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  /// A file holding "old\n" with `mode`.
  std::string file_with_mode(const std::string& name, mode_t mode) const {
    const std::string p = (dir_ / name).string();
    std::ofstream(p) << "old\n";
    ::chmod(p.c_str(), mode);
    return p;
  }
  fs::path dir_;
};

TEST_F(OutputCheck, AFileWithNoWriteBitIsRefusedForEveryUserRootToo) {
  const std::string p = file_with_mode("r.off", 0444);
  SCOPED_TRACE(::geteuid() == 0 ? "as root" : "as a user");
  try {
    check_output_files({{"-o", p}}, {});
    FAIL() << "a write-protected file was accepted as an output";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("exists and is not writable"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("-o"), std::string::npos) << e.what();
  }
  // Nothing changed, nothing created beside it.
  std::ifstream in(p);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "old\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

// Any one write bit is enough for the rule (permission itself is the access check's: as a user,
// a file only its group may write is still refused by that one).
TEST_F(OutputCheck, AFileWithAWriteBitIsAcceptedByTheModeRule) {
  EXPECT_NO_THROW(check_output_files({{"-o", file_with_mode("a.off", 0644)}}, {}));
  EXPECT_NO_THROW(check_output_files({{"--log", file_with_mode("b.csv", 0600)}}, {}));
  if (::geteuid() == 0) {
    EXPECT_NO_THROW(check_output_files({{"-o", file_with_mode("c.off", 0464)}}, {}));
  }
}

}  // namespace
}  // namespace shellcontract
