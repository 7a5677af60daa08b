// A file the file system refuses is an InputFileError or OutputFileError with the errno of the
// call that failed and the path (shellcontract/file_error.hpp), so that a front end can report
// it in its own terms (Python: FileNotFoundError, IsADirectoryError, ...). Before, they were a
// plain InputError or UsageError, with the reason only in the message's words. The message and
// the error's base class (the CLI's exit code) are unchanged, and a file read but refused for
// its content carries no errno.
#include <gtest/gtest.h>

#include <cerrno>
#include <filesystem>
#include <string>

#include "shellcontract/checkpoint.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/file_error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/output_files.hpp"
#include "support/scratch_dir.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

class FileErrors : public test::ScratchDirTest {
 protected:
  FileErrors() : ScratchDirTest("file_errors_") {}
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
};

/// The Error (InputFileError or OutputFileError) `act` throws, checked to be about `file` with
/// `error_number`; its message.
template <typename Error, typename Act>
std::string file_error(Act act, const char* kind, const std::string& file, int error_number) {
  try {
    act();
  } catch (const Error& e) {
    EXPECT_EQ(e.error_number(), error_number) << e.what();
    EXPECT_EQ(e.path(), file);
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an " << kind << ": " << e.what();
    return "";
  }
  ADD_FAILURE() << "nothing thrown";
  return "";
}

template <typename Read>
std::string input_file_error(Read read, const std::string& file, int error_number) {
  return file_error<InputFileError>(read, "InputFileError", file, error_number);
}

template <typename Write>
std::string output_file_error(Write write, const std::string& file, int error_number) {
  return file_error<OutputFileError>(write, "OutputFileError", file, error_number);
}

TEST_F(FileErrors, AMissingInputIsENOENTWithTheSameMessage) {
  const std::string p = path("missing.off");
  EXPECT_EQ(input_file_error([&] { read_input_mesh(p); }, p, ENOENT),
            p + ": cannot open file: no such file");
}

TEST_F(FileErrors, AFolderAsInputIsEISDIR) {
  std::filesystem::create_directory(path("folder.off"));
  EXPECT_EQ(
      input_file_error([&] { read_input_mesh(path("folder.off")); }, path("folder.off"), EISDIR),
      path("folder.off") + ": cannot open file: it is a folder");
  // Without a mesh's extension: what the path is comes before the extension's refusal.
  const std::string d = dir_.string();
  input_file_error([&] { read_input_mesh(d); }, d, EISDIR);
}

TEST_F(FileErrors, AnInputUnderAFileIsENOTDIR) {
  write("file", "x");
  const std::string p = path("file") + "/mesh.off";
  input_file_error([&] { read_input_mesh(p); }, p, ENOTDIR);
}

TEST_F(FileErrors, AMissingCheckpointKeepsItsErrnoUnderItsOwnWords) {
  const std::string p = path("missing.ckpt");
  const std::string what = input_file_error([&] { load_checkpoint(p); }, p, ENOENT);
  EXPECT_EQ(what, "checkpoint " + p + ": cannot open file: no such file");
}

TEST_F(FileErrors, AContentRefusalCarriesNoErrno) {
  const std::string p = write("bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n");
  try {
    read_input_mesh(p);
    FAIL() << "a truncated OFF was read";
  } catch (const InputError& e) {
    EXPECT_EQ(dynamic_cast<const FileSystemFailure*>(&e), nullptr) << e.what();
  }
}

TEST_F(FileErrors, WritingIntoAMissingFolderIsENOENT) {
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/ico1.off");
  const std::string p = path("no_such_folder") + "/out.off";
  const std::string what =
      output_file_error([&] { write_mesh_atomic(p, mesh, positions_from_mesh(mesh)); }, p, ENOENT);
  EXPECT_EQ(what.rfind("cannot write '" + p + "': cannot create a file in the folder", 0), 0u)
      << what;
}

TEST_F(FileErrors, WritingOntoAFolderIsEISDIR) {
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/ico1.off");
  std::filesystem::create_directory(path("out.off"));
  EXPECT_EQ(output_file_error(
                [&] { write_mesh_atomic(path("out.off"), mesh, positions_from_mesh(mesh)); },
                path("out.off"), EISDIR),
            "cannot write '" + path("out.off") + "': it is a folder");
  // A folder without a mesh's extension is refused before the extension is.
  const std::string d = dir_.string();
  output_file_error([&] { write_mesh_atomic(d, mesh, positions_from_mesh(mesh)); }, d, EISDIR);
}

TEST_F(FileErrors, AnOutputCheckOfAMissingFolderIsENOENT) {
  const std::string p = path("no_such_folder") + "/run.ckpt";
  const std::string what = output_file_error(
      [&] {
        check_output_files({{"--checkpoint", p}}, {});
      },
      p, ENOENT);
  EXPECT_NE(what.find("does not exist"), std::string::npos) << what;
  output_file_error(
      [&] {
        check_output_files({{"--checkpoint", dir_.string()}}, {});
      },
      dir_.string(), EISDIR);
}

}  // namespace
}  // namespace shellcontract
