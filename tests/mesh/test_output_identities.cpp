// check_output_files in process (shellcontract/output_files.hpp): the identity rules and the
// promise that the check creates nothing that stays. The CLI's hostile tests show the same rules
// end to end through a run; these hold for the library alone (the Python module's write_mesh and
// contract() call it without the CLI), with no run to hide behind.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "shellcontract/error.hpp"
#include "shellcontract/output_files.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

class OutputIdentities : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("shellcontract_output_identities_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name, const std::string& text) const {
    const std::string p = (dir_ / name).string();
    std::ofstream(p) << text;
    return p;
  }
  std::vector<std::string> entries() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  }
  /// The message of the refusal of `outputs` given `inputs`, or "" when they pass.
  static std::string refusal(const std::vector<NamedFile>& outputs,
                             const std::vector<NamedFile>& inputs) {
    try {
      check_output_files(outputs, inputs);
    } catch (const UsageError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(OutputIdentities, AHardLinkToTheInputIsTheInput) {
  const std::string in = file("in.off", "OFF\n");
  const std::string link = (dir_ / "out.off").string();
  fs::create_hard_link(in, link);
  const std::string why = refusal({{"-o", link}}, {{"INPUT", in}});
  EXPECT_NE(why.find("is the input file"), std::string::npos) << why;
}

TEST_F(OutputIdentities, TwoOutputsOnOneFileAreRefusedWhateverTheyAreCalled) {
  const std::string a = (dir_ / "a.csv").string();
  const std::string a_again = (dir_ / "." / "a.csv").string();  // not there yet: folder and name
  std::string why = refusal({{"-o", a}, {"--log", a_again}}, {});
  EXPECT_NE(why.find("each output needs its own file"), std::string::npos) << why;
  EXPECT_NE(why.find("--log"), std::string::npos) << why;
  // An existing file and a hard link to it: one file, two names.
  const std::string b = file("b.csv", "old\n"), b_link = (dir_ / "b_link.csv").string();
  fs::create_hard_link(b, b_link);
  why = refusal({{"-o", b}, {"--summary", b_link}}, {});
  EXPECT_NE(why.find("each output needs its own file"), std::string::npos) << why;
  EXPECT_EQ(refusal({{"-o", a}, {"--summary", b}}, {}), "") << "two different files pass";
}

TEST_F(OutputIdentities, AFileTheInputMeshReadsIsNeverAnOutput) {
  // An OBJ's material library is an input too, existing or not (output_files.hpp).
  const std::string obj = file("m.obj",
                               "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                               "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
  const std::string mtl = (dir_ / "m.mtl").string();
  std::string why = refusal({{"--log", mtl}}, {{"INPUT", obj}});
  EXPECT_NE(why.find("the input needs this file"), std::string::npos) << why;
  file("m.mtl", "newmtl a\n");
  why = refusal({{"--log", mtl}}, {{"INPUT", obj}});
  EXPECT_NE(why.find("the input needs this file"), std::string::npos) << why;
}

TEST_F(OutputIdentities, AFolderInTheOutputsPlaceIsRefused) {
  fs::create_directories(dir_ / "out.off");
  const std::string why = refusal({{"-o", (dir_ / "out.off").string()}}, {});
  EXPECT_NE(why.find("is a folder"), std::string::npos) << why;
}

TEST_F(OutputIdentities, TheCheckCreatesNothingThatStays) {
  const std::string kept = file("kept.off", "old\n");
  const std::string fresh = (dir_ / "new.csv").string();
  ASSERT_EQ(refusal({{"-o", kept}, {"--log", fresh}}, {}), "");
  EXPECT_EQ(entries(), std::vector<std::string>{"kept.off"}) << "the folder probe was left behind";
  std::ifstream in(kept);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()),
            "old\n");
}

}  // namespace
}  // namespace shellcontract
