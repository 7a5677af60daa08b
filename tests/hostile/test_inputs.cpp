// Inputs are regular files, read completely or refused. The CLI runs under
// `timeout` and a memory limit, so that the code before the fix (which read devices and FIFOs
// until memory ran out, or waited for a FIFO's writer forever) fails these tests instead of
// hanging them.
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <regex>

#include "hostile/hostile_support.hpp"
#include "support/forged_checkpoint.hpp"
#include "support/gltf_files.hpp"

namespace shellcontract {
namespace {

using test::Hostile;

/// The CLI with at most 60 s and 3 GB of address space.
test::RunResult bounded_cli(const std::vector<std::string>& args) {
  return test::run_command("ulimit -v 3000000 && exec timeout 60 " + test::cli_command(args));
}

// Before: /dev/zero named like a mesh was read until memory ran out.
TEST_F(Hostile, ADeviceAsTheMeshIsRefusedAtOnce) {
  const fs::path zero = dir_ / "zero.off";
  std::string why;
  if (!make_device(zero, 5, why)) SKIP_OR_FAIL_UNDER_CI(why);
  const auto r = bounded_cli({"check", zero.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("not a regular file"), std::string::npos) << r.output;
}

// Before: opening a FIFO waited for a writer forever (timeout: exit 124).
TEST_F(Hostile, AFifoAsTheMeshIsRefusedAtOnce) {
  const fs::path fifo = dir_ / "in.off";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0666), 0);
  const auto r = bounded_cli({"run", fifo.string(), "-o", (dir_ / "o.off").string(), "-q"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("FIFO"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "o.off"));
}

// A .gltf's external buffer is read like the mesh: a FIFO or a device named by its uri is refused
// at once. tinygltf's own file callbacks would have opened the FIFO to see whether it exists
// (waiting for a writer forever) and read /dev/zero until memory ran out. Before the glTF
// reader: "unknown extension '.gltf'".
TEST_F(Hostile, AFifoOrADeviceAsAGltfBufferIsRefusedAtOnce) {
  test::GltfScene s;
  s.primitives.push_back(test::octahedron_primitive(false, false));
  const test::GltfParts parts = test::gltf_parts(s);
  ASSERT_EQ(::mkfifo((dir_ / "fifo.bin").c_str(), 0666), 0);
  test::spit(dir_ / "fifo.gltf", test::gltf_text(parts, "fifo.bin"));
  auto r =
      bounded_cli({"run", (dir_ / "fifo.gltf").string(), "-o", (dir_ / "o.off").string(), "-q"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("fifo.bin"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("FIFO"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "o.off"));
  std::string why;
  if (!make_device(dir_ / "zero.bin", 5, why)) SKIP_OR_FAIL_UNDER_CI(why);
  test::spit(dir_ / "zero.gltf", test::gltf_text(parts, "zero.bin"));
  r = bounded_cli({"check", (dir_ / "zero.gltf").string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("not a regular file"), std::string::npos) << r.output;
}

// Before: a folder as --regions FILE, and /dev/zero as one, were read with getline.
TEST_F(Hostile, ADeviceAsTheRegionFileIsRefusedAtOnce) {
  const fs::path zero = dir_ / "zero.txt";
  std::string why;
  if (!make_device(zero, 5, why)) SKIP_OR_FAIL_UNDER_CI(why);
  const auto r = bounded_cli({"run", test::mesh("bumpy_sphere.off"), "-o", (dir_ / "o.off").string(), "-n", "2",
                              "-q", "--regions", zero.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("not a regular file"), std::string::npos) << r.output;
}

// Before: a 1 GB sparse region file took 22 s and 6.3 GB; now its size is refused before a byte
// is read (a region file of this mesh cannot need more than about 1 MB).
TEST_F(Hostile, ARegionFileFarLargerThanTheMeshIsRefused) {
  const fs::path big = dir_ / "big.txt";
  test::spit(big, "");
  fs::resize_file(big, std::uintmax_t{1} << 30);
  const auto r = bounded_cli({"run", test::mesh("bumpy_sphere.off"), "-o", (dir_ / "o.off").string(), "-n", "2",
                              "-q", "--regions", big.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("too large"), std::string::npos) << r.output;
}

// Review 7 (F6): the weights file, as the face list: a 1 GB sparse file was read whole and copied
// (4.2 GB) before its first line was refused; under this test's memory limit that ended in "out
// of memory", exit 3, naming no file. Now its size is refused before a byte is read.
TEST_F(Hostile, AWeightsFileFarLargerThanTheMeshIsRefused) {
  const fs::path big = dir_ / "big.txt";
  test::spit(big, "");
  fs::resize_file(big, std::uintmax_t{1} << 30);
  const auto r = bounded_cli({"run", test::mesh("ico2.off"), "-o", (dir_ / "o.off").string(), "-n",
                              "2", "-q", "--region-weights", big.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(big.string() + ": file too large"), std::string::npos) << r.output;
}

// The same with --checkpoint, which hashes the weights file (and a face list) before the mesh, and
// so before the reader that bounds it: the file was read whole to be hashed, and a 256 MiB one
// ended in "out of memory" (exit 3) under a 200 MB limit (the run itself fits in it). Now it is
// hashed a piece at a time and the reader refuses it as without a checkpoint.
TEST_F(Hostile, AWeightsFileOrFaceListFarLargerThanTheMeshIsRefusedWithACheckpointToo) {
  const fs::path big = dir_ / "big.txt";
  test::spit(big, "");
  fs::resize_file(big, std::uintmax_t{256} << 20);
  for (const char* option : {"--region-weights", "--regions"}) {
    const auto r = test::run_command(
        "ulimit -v 200000 && exec timeout 60 " +
        test::cli_command({"run", test::mesh("ico2.off"), "-o", (dir_ / "o.off").string(), "-n",
                           "2", "-q", "--checkpoint", (dir_ / "c.ckpt").string(), option,
                           big.string()}));
    EXPECT_EQ(r.exit_code, 2) << option << ": " << r.output;
    EXPECT_NE(r.output.find(big.string() + ": file too large"), std::string::npos)
        << option << ": " << r.output;
  }
}

// Review 7 (F6): --resume of a file that is no checkpoint is refused after its first bytes,
// whatever its size, and a checkpoint larger than the machine's memory before it is read. Both
// were read whole: "out of memory", exit 3, naming no file (here, sparse files: no disk).
TEST_F(Hostile, AHugeFileAsTheCheckpointIsRefusedUnread) {
  const fs::path zeros = dir_ / "zeros.ckpt", big = dir_ / "big.ckpt";
  const std::string out = (dir_ / "o.off").string();
  test::spit(zeros, "");
  fs::resize_file(zeros, std::uintmax_t{50} << 30);
  auto r = bounded_cli({"run", "--resume", zeros.string(), "-o", out, "-q"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("checkpoint " + zeros.string() + ": not a shellcontract checkpoint"),
            std::string::npos)
      << r.output;
  test::spit(big, "SHELLCONTRACT-CHECKPOINT\n");
  const std::uintmax_t memory = static_cast<std::uintmax_t>(::sysconf(_SC_PHYS_PAGES)) *
                                static_cast<std::uintmax_t>(::sysconf(_SC_PAGE_SIZE));
  fs::resize_file(big, memory + 1);
  r = bounded_cli({"run", "--resume", big.string(), "-o", out, "-q"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("checkpoint " + big.string() + ": file too large: " +
                          std::to_string(memory + 1) + " bytes, more than this machine's memory"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(out));
}

// Review 7 (F7): a checkpoint resealed by hand (its checksum is FNV-1a, no key) whose count of
// inputs is as large as the file. The reader allocated the entries (some 80 bytes each) before it
// found them past the end: 3.8 GB for this 48 MB file, "out of memory" (exit 3) under this test's
// limit. Now the count is refused against the bytes left (exit 2).
TEST_F(Hostile, AForgedCheckpointCountIsRefusedBeforeItIsAllocated) {
  std::string b = "SHELLCONTRACT-CHECKPOINT\n";
  const auto put = [&b](auto v) { b.append(reinterpret_cast<const char*>(&v), sizeof v); };
  put(std::uint32_t{3});  // format, version "v", input "i", the input's hash
  put(std::uint64_t{1});
  b += 'v';
  put(std::uint64_t{1});
  b += 'i';
  put(std::uint64_t{0});
  const std::uint64_t size = std::uint64_t{48} << 20;
  put(size);  // the count of inputs
  b.resize(size, '\0');
  const fs::path forged = dir_ / "forged.ckpt";
  test::spit(forged, test::resealed(b));
  const auto r =
      bounded_cli({"run", "--resume", forged.string(), "-o", (dir_ / "o.off").string(), "-q"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(std::to_string(size) + " inputs of at least 25 bytes each"),
            std::string::npos)
      << r.output;
}

// Before: the message quoted the token up to its first NUL ("'" and nothing after).
TEST_F(Hostile, ARegionFileWithNulBytesGetsAPrintableMessage) {
  const fs::path f = dir_ / "nul.txt";
  test::spit(f, std::string("1 2\n3 a\0b 4\n", 12));
  const auto r = bounded_cli({"run", test::mesh("bumpy_sphere.off"), "-o", (dir_ / "o.off").string(), "-n", "2",
                              "-q", "--regions", f.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("'a\\x00b' is not a face index"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find('\0'), std::string::npos);
}

// Before: the weights and point-set readers quoted their tokens as they were (ESC, BEL and
// \x01 reached the terminal), and every reader's escaping let 0xFF or a UTF-8 encoded C1
// control (U+009B, a CSI to a UTF-8 terminal) through. Well-formed UTF-8 stays readable.
TEST_F(Hostile, ControlAndNonUtf8BytesOfAnInputAreEscapedInItsMessage) {
  const std::string nasty = "a\x1b[31m\x07\xff\xc2\x9b\xc3\xa9";  // ESC [31m BEL 0xFF U+009B e-acute
  const std::string shown = "a\\x1b[31m\\x07\\xff\\xc2\\x9b\xc3\xa9";
  test::spit(dir_ / "w.txt", nasty + "\n");
  test::spit(dir_ / "r.txt", "1 2 " + nasty + "\n");
  test::spit(dir_ / "p.xyz", "1 2 " + nasty + " 4 5 6\n");
  const std::string mesh = test::mesh("ico2.off"), out = (dir_ / "o.off").string();
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"run", mesh, "-o", out, "-q", "--region-weights", (dir_ / "w.txt").string()},
        std::vector<std::string>{"run", mesh, "-o", out, "-q", "--regions", (dir_ / "r.txt").string()},
        std::vector<std::string>{"reconstruct", (dir_ / "p.xyz").string(), "-o", out}}) {
    const auto r = test::run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("'" + shown + "'"), std::string::npos) << args[4] << ": " << r.output;
    for (const char c : {'\x1b', '\x07', '\xff', '\x9b'})
      EXPECT_EQ(r.output.find(c), std::string::npos) << args[4] << ": a raw byte " << int(static_cast<unsigned char>(c));
  }
}

/// Closed tetrahedron number t of an OBJ (vertices 4t+1 .. 4t+4).
std::string tetrahedron(int t) {
  const std::string x = std::to_string(3 * t), x1 = std::to_string(3 * t + 1);
  std::string s = "v " + x + " 0 0\nv " + x1 + " 0 0\nv " + x + " 1 0\nv " + x + " 0 1\n";
  const int b = 4 * t + 1;
  for (const auto& f : {std::array<int, 3>{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}})
    s += "f " + std::to_string(b + f[0]) + " " + std::to_string(b + f[1]) + " " + std::to_string(b + f[2]) + "\n";
  return s;
}

// Before: memory running out while the file's bytes were read (`stream << rdbuf()`) was
// swallowed, and the part read so far was taken for the file. The file here is a tetrahedron,
// 24 MB of comment lines, and a second tetrahedron: any prefix is a usable one-tetrahedron mesh,
// cheap to parse. The code before the fix answered exit 0 with 4 faces at 6 of these 17 limits.
// Now: the whole mesh (8 faces) or exit 2.
TEST_F(Hostile, OutOfMemoryWhileReadingIsNeverAHalfMesh) {
  const fs::path obj = dir_ / "padded.obj";
  {
    std::ofstream out(obj, std::ios::binary);
    out << tetrahedron(0);
    const std::string comment = "# " + std::string(98, 'p') + "\n";
    for (int i = 0; i < 24 * 1024 * 1024 / 100; ++i) out << comment;
    out << tetrahedron(1);
  }
  const std::regex faces_line("\"faces\": ([0-9]+)");
  int refused = 0, whole = 0;
  for (long kib = 16000; kib <= 80000; kib += 4000) {
    const auto r = test::run_command("ulimit -v " + std::to_string(kib) + " && exec timeout 120 " +
                                     test::cli_command({"check", obj.string(), "--json"}));
    std::smatch m;
    if (r.exit_code == 0 && std::regex_search(r.output, m, faces_line)) {
      EXPECT_EQ(m[1].str(), "8") << "a part of the file was read as the mesh at " << kib << " KiB";
      ++whole;
    } else {
      // Memory running out is exit 3 wherever it strikes (README, "Exit codes"), not 2: the
      // file is not to blame.
      EXPECT_EQ(r.exit_code, 3) << kib << " KiB:\n" << r.output.substr(0, 400);
      EXPECT_NE(r.output.find("out of memory"), std::string::npos) << r.output.substr(0, 400);
      ++refused;
    }
  }
  std::printf("refused %d times, read whole %d times\n", refused, whole);
}

// The tool maps its first MiB of stack at start (cli/entry.cpp). Under a stack limit below it,
// or an address-space limit the program's own mappings nearly fill, that mapping was a SIGSEGV
// (the exit code a crash: -1 here) instead of memory's exit 3 and a message.
TEST_F(Hostile, AStackLimitBelowTheToolsStackIsOutOfMemoryNotACrash) {
  const auto r =
      test::run_command("ulimit -s 256 && exec " +
                        test::cli_command({"check", test::MESH_DIR + std::string("/ico1.off")}));
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("out of memory at start: the stack limit (ulimit -s) is 256 KiB"),
            std::string::npos)
      << r.output;
}

}  // namespace
}  // namespace shellcontract
