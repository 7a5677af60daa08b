// A file the file system refuses is an InputFileError or OutputFileError with the errno of the
// call that failed and the path (shellcontract/file_error.hpp), so that a front end can report
// it in its own terms (Python: FileNotFoundError, IsADirectoryError, ...). Before, they were a
// plain InputError or UsageError, with the reason only in the message's words. The message and
// the error's base class (the CLI's exit code) are unchanged, and a file read but refused for
// its content carries no errno.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "mesh/file_safety.hpp"
#include "mesh/soup_writer.hpp"
#include "shellcontract/checkpoint.hpp"
#include "shellcontract/checkpoint_lock.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/file_error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/output_files.hpp"
#include "support/gltf_files.hpp"
#include "support/scratch_dir.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

class FileErrors : public test::ScratchDirTest {
 protected:
  FileErrors() : ScratchDirTest("file_errors_") {}
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  /// A .gltf of one triangle whose buffer is the external file `uri`.
  std::string gltf_with_buffer(const std::string& uri) const {
    test::GltfScene scene;
    scene.primitives.push_back({{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {}, {}, {0, 1, 2}});
    return write("mesh.gltf", test::gltf_text(test::gltf_parts(scene), uri));
  }
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

// A device, a FIFO or a socket is refused for what it is, not by a failed call: a file error
// without an errno (NO_ERRNO), about the path. Before, a plain InputError or UsageError.
TEST_F(FileErrors, ADeviceOrFifoAsInputIsAFileErrorWithoutErrno) {
  const std::string fifo = path("fifo.off");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0666), 0);
  EXPECT_EQ(input_file_error([&] { read_input_mesh(fifo); }, fifo, FileSystemFailure::NO_ERRNO),
            fifo + ": not a regular file: it is a FIFO (named pipe); inputs must be regular files");
  EXPECT_EQ(input_file_error([&] { read_regular_file("/dev/null"); }, "/dev/null",
                             FileSystemFailure::NO_ERRNO),
            "/dev/null: not a regular file: it is a device; inputs must be regular files");
}

TEST_F(FileErrors, AnInputOverItsSizeLimitIsEFBIG) {
  const std::string p = write("big.txt", std::string(100, 'x'));
  EXPECT_EQ(input_file_error([&] { read_regular_file(p, 10); }, p, EFBIG),
            p + ": file too large: 100 bytes, more than the 10 this file can need");
}

TEST_F(FileErrors, AFifoInAnOutputsPlaceIsAFileErrorWithoutErrno) {
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/ico1.off");
  const std::string fifo = path("fifo.off");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0666), 0);
  EXPECT_EQ(output_file_error([&] { write_mesh_atomic(fifo, mesh, positions_from_mesh(mesh)); },
                              fifo, FileSystemFailure::NO_ERRNO),
            "cannot write '" + fifo +
                "': it exists and is not a regular file (a device, FIFO or socket is never "
                "replaced)");
  EXPECT_EQ(output_file_error(
                [&] {
                  check_output_files({{"--checkpoint", fifo}}, {});
                },
                fifo, FileSystemFailure::NO_ERRNO),
            "--checkpoint '" + fifo +
                "': exists and is not a regular file (a device, FIFO or socket); it is never "
                "replaced");
}

// Before: a device or FIFO named without a mesh's extension was refused for its name first ("the
// file name has no extension", a plain UsageError), not for what it is; a folder's message named
// the extensions too. /dev/null is only stat'ed here, never opened: refused for its name even
// without that check. The repaired mesh's writer, write_polygon_soup_atomic, checks the same way.
TEST_F(FileErrors, ADeviceFifoOrFolderWithoutAMeshExtensionIsRefusedForWhatItIs) {
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/ico1.off");
  const std::vector<Point3> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<std::vector<std::size_t>> polygons{{0, 1, 2}};
  const std::string fifo = path("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0666), 0);
  for (const std::string& p : {fifo, std::string("/dev/null")}) {
    const std::string expected = "cannot write '" + p +
                                 "': it exists and is not a regular file (a device, FIFO or socket "
                                 "is never replaced)";
    EXPECT_EQ(output_file_error([&] { write_mesh_atomic(p, mesh, positions_from_mesh(mesh)); }, p,
                                FileSystemFailure::NO_ERRNO),
              expected);
    EXPECT_EQ(output_file_error([&] { write_polygon_soup_atomic(p, points, polygons); }, p,
                                FileSystemFailure::NO_ERRNO),
              expected);
  }
  const std::string d = path("folder");
  std::filesystem::create_directory(d);
  for (const auto& write : std::vector<std::function<void()>>{
           [&] { write_mesh_atomic(d, mesh, positions_from_mesh(mesh)); },
           [&] { write_polygon_soup_atomic(d, points, polygons); }})
    EXPECT_EQ(output_file_error(write, d, EISDIR), "cannot write '" + d + "': it is a folder");
  std::vector<std::string> left;  // no temporary
  for (const auto& e : std::filesystem::directory_iterator(dir_))
    left.push_back(e.path().filename().string());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"fifo", "folder"}));
}

// What flock says of a lock another run holds: EWOULDBLOCK, about the checkpoint (the lock
// file is named in the message). Before, a plain UsageError.
TEST_F(FileErrors, ACheckpointLockedByAnotherRunIsEWOULDBLOCK) {
  const std::string checkpoint = path("run.ckpt");
  const int held = ::open(checkpoint_lock_path(checkpoint).c_str(), O_RDWR | O_CREAT, 0666);
  ASSERT_GE(held, 0);
  ASSERT_EQ(::flock(held, LOCK_EX | LOCK_NB), 0);
  std::vector<std::string> warnings;
  const std::string what =
      output_file_error([&] { lock_checkpoint(checkpoint, "--checkpoint", true, warnings); },
                        checkpoint, EWOULDBLOCK);
  ::close(held);
  EXPECT_EQ(what.rfind("--checkpoint '" + checkpoint +
                           "': another shellcontract run is saving to this checkpoint",
                       0),
            0u)
      << what;
}

// A checkpoint named through a symbolic link is the link's target (a save replaces the target):
// its lock, log and history are the target's, so a second run naming the target itself is
// refused. Before, the link's name gave another lock file: both runs saved to one file.
TEST_F(FileErrors, ACheckpointThroughALinkTakesItsTargetsLock) {
  const std::string target = path("run.ckpt"), link = path("link.ckpt");
  std::filesystem::create_symlink("run.ckpt", link);
  EXPECT_EQ(checkpoint_lock_path(link), checkpoint_lock_path(target));
  EXPECT_EQ(checkpoint_log_path(link), target + ".log");
  EXPECT_EQ(checkpoint_history_path(link), target + ".history");
  std::vector<std::string> warnings;
  const auto held = lock_checkpoint(link, "--checkpoint", true, warnings);
  ASSERT_NE(held, nullptr);
  output_file_error([&] { lock_checkpoint(target, "--checkpoint", true, warnings); }, target,
                    EWOULDBLOCK);
}

// A glTF whose external buffer cannot be had: the error is about the buffer, with the errno
// the file system gave for it; the message names the .gltf, as before. Before, a plain
// InputError.
TEST_F(FileErrors, AGltfBufferThatCannotBeHadIsAFileErrorAboutTheBuffer) {
  const std::string missing = gltf_with_buffer("nowhere.bin");
  EXPECT_EQ(input_file_error([&] { read_input_mesh(missing); }, path("nowhere.bin"), ENOENT),
            missing + ": cannot read .gltf: tinygltf: File not found : nowhere.bin");
  write("file", "x");
  const std::string under_a_file = gltf_with_buffer("file/mesh.bin");
  input_file_error([&] { read_input_mesh(under_a_file); }, path("file") + "/mesh.bin", ENOTDIR);
  std::filesystem::create_directory(path("folder.bin"));
  const std::string folder = gltf_with_buffer("folder.bin");
  input_file_error([&] { read_input_mesh(folder); }, path("folder.bin"), EISDIR);
  // A buffer that is read but is too short is refused for its content: no errno.
  write("short.bin", "abcd");
  const std::string short_buffer = gltf_with_buffer("short.bin");
  try {
    read_input_mesh(short_buffer);
    ADD_FAILURE() << "a buffer shorter than its byteLength was read";
  } catch (const InputError& e) {
    EXPECT_EQ(dynamic_cast<const FileSystemFailure*>(&e), nullptr) << e.what();
  }
}

}  // namespace
}  // namespace shellcontract
