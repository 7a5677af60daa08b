// Hostile glTF inputs on the command line (review7 F1, F2): a JSON nested 20,000 levels deep is
// exit 2 naming the file, not a crash, in `check` and in `run` (also where tinygltf does not
// read the nested member and the crash came only when the result was written); an external
// buffer file of 20 GiB is refused by its size without being read, under a memory limit far
// below it. Before: exit by SIGSEGV (stack overflow) for the JSON, and the buffer file was read
// whole (twice) before its size was compared with byteLength (under the limit: bad_alloc).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "support/cli_runner.hpp"
#include "support/gltf_files.hpp"
#include "support/scratch_dir.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

class CliGltfHostile : public test::ScratchDirTest {
 protected:
  CliGltfHostile() : ScratchDirTest("shellcontract_cli_gltf_hostile_") {}
  std::string out(const std::string& name) const { return (dir_ / name).string(); }
};

test::GltfScene octahedron(const std::string& extra = "") {
  test::GltfScene s;
  s.primitives.push_back(test::octahedron_primitive(true, true));
  s.extra = extra;
  return s;
}

std::string nested(std::size_t arrays) {
  return std::string(arrays, '[') + std::string(arrays, ']');
}

TEST_F(CliGltfHostile, ADeeplyNestedJsonIsExitTwoNamingTheFileNotACrash) {
  const test::GltfParts extras = test::gltf_parts(octahedron("\"extras\":" + nested(20000)));
  // A member tinygltf does not read: before, read fine and the crash came with the result.
  const test::GltfParts unknown = test::gltf_parts(octahedron("\"foo\":" + nested(100000)));
  test::GltfParts on_node = test::gltf_parts(octahedron());
  on_node.json.replace(on_node.json.find("{\"mesh\":0"), 9,
                       "{\"mesh\":0,\"extras\":" + nested(20000));
  const std::vector<std::string> files = {
      write("extras.glb", test::glb_bytes(extras)), write("extras.gltf", test::gltf_text(extras)),
      write("unknown.glb", test::glb_bytes(unknown)), write("node.gltf", test::gltf_text(on_node))};
  for (const std::string& in : files) {
    const std::string result = out("result." + fs::path(in).extension().string().substr(1));
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{"check", in},
          std::vector<std::string>{"run", in, "-o", result, "-n", "2", "-q"},
          std::vector<std::string>{"run", in, "-o", out("result.off"), "-n", "2", "-q"}}) {
      const auto r = test::run_cli(args);
      EXPECT_EQ(r.exit_code, 2) << args[0] << " " << in << ": " << r.output;
      EXPECT_NE(
          r.output.find(in + ": JSON nested too deeply: the JSON nests deeper than 512 levels"),
          std::string::npos)
          << r.output;
      EXPECT_FALSE(fs::exists(result)) << in;
    }
  }
  // 512 levels (the root object and 511 arrays) are read and written back.
  const std::string ok =
      write("d512.glb", test::glb_bytes(test::gltf_parts(octahedron("\"extras\":" + nested(511)))));
  const auto r = test::run_cli({"run", ok, "-o", out("d512_out.glb"), "-n", "2", "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out("d512_out.glb")));
}

TEST_F(CliGltfHostile, AHugeBufferFileIsRefusedByItsSizeUnread) {
  const test::GltfParts parts = test::gltf_parts(octahedron());
  // Sparse: no disk blocks; reading it would ask for 20 GiB, ten times the limit below.
  const std::string bin = out("huge.bin");
  write("huge.bin", "");
  fs::resize_file(bin, 20ull << 30);
  const std::string gltf = write("huge.gltf", test::gltf_text(parts, "huge.bin"));
  std::string claims = test::gltf_text(parts, "huge.bin");
  const std::string length = "\"byteLength\":" + std::to_string(parts.bin.size());
  claims.replace(claims.find(length), length.size(), "\"byteLength\":1099511627776");
  const std::string big = write("claims.gltf", claims);  // byteLength 1 TiB: still not read
  const long limit_kib = 2L << 20;                       // 2 GiB of address space
  for (const auto& [in, expected] :
       {std::pair<std::string, std::string>{gltf, "bytes, more than buffer 0's byteLength of " +
                                                      std::to_string(parts.bin.size()) +
                                                      " ('huge.bin'); it was not read"},
        std::pair<std::string, std::string>{big,
                                            "bytes, more than 4294967295, the most a buffer "
                                            "is read with (4 GiB, as a file; buffer 0's "
                                            "byteLength is 1099511627776); it was not read"}})
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{"check", in},
          std::vector<std::string>{"run", in, "-o", out("o.gltf"), "-n", "2", "-q"}}) {
      const auto r = test::run_cli_limited(limit_kib, args);
      EXPECT_EQ(r.exit_code, 2) << r.output;
      EXPECT_NE(r.output.find(in + ": buffer file too large: '" + bin + "' has 21474836480 bytes"),
                std::string::npos)
          << r.output;
      EXPECT_NE(r.output.find(expected), std::string::npos) << r.output;
    }
}

}  // namespace
}  // namespace shellcontract
