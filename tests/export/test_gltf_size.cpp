// The .glb's size (src/export/gltf_size.hpp): the bound known before the frames exist is an upper
// bound of the file written, and close to it; the writer refuses a file over the limit of a .glb
// (4 GiB - 1 bytes, lowered here through the test hook) before writing a byte, and writes one at
// the limit.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "export/gltf_size.hpp"
#include "export_fixtures.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/export.hpp"
#include "support/mesh_fixtures.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

/// The limit lowered for one test, restored after it.
struct LoweredLimit {
  explicit LoweredLimit(std::uint64_t bytes) { gltf::set_glb_max_bytes_for_test(bytes); }
  ~LoweredLimit() { gltf::set_glb_max_bytes_for_test(0); }
};

/// A run's .glb as the CLI makes it: frames, each frame's mean curvature, four end fields.
GltfAnimation run_animation(int levels, int frames) {
  const test::TriMesh s = test::icosphere(levels, 2.0);
  GltfAnimation a;
  a.faces = s.faces;
  a.frame_fields.push_back({"mean_curvature", {}});
  for (int f = 0; f <= frames; ++f) {
    a.frame_numbers.push_back(f);
    a.frames.push_back(test::fake_frame(s.x, f, frames));
    a.frame_fields[0].second.push_back(a.frames.back().col(2).cast<float>());
  }
  for (const char* name : {"mean_curvature", "gaussian_curvature", "pressure", "energy_density"})
    a.colour_fields.push_back({name, s.x.col(0)});
  return a;
}

/// What the bound is given before the run: frame 0 and the fields by name.
GltfAnimation layout_of(const GltfAnimation& a) {
  GltfAnimation layout = a;
  layout.frames.resize(1);
  layout.frame_numbers.resize(1);
  for (auto& f : layout.frame_fields) f.second.clear();
  for (NamedVertexField& f : layout.colour_fields) f.values.resize(0);
  return layout;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(GlbSize, TheBoundBeforeTheRunIsAnUpperBoundOfTheFileAndClose) {
  test::ScratchDir dir("glb_size");
  for (const auto& [levels, frames] : {std::pair{3, 4}, std::pair{5, 20}}) {
    const GltfAnimation a = run_animation(levels, frames);
    const GltfAnimation layout = layout_of(a);
    const std::uint64_t bound =
        gltf::glb_size_bound(layout, a.frames.size(), gltf::glb_vertices(layout));
    const std::string path = dir.file("run.glb");
    const GltfStats stats = write_gltf_animation(path, a);
    ASSERT_EQ(stats.bytes, fs::file_size(path));
    EXPECT_GE(bound, stats.bytes) << levels << " levels, " << frames << " frames";
    // Close where the frames make the file large: the JSON's allowance is a few tens of KiB.
    if (levels == 5) {
      EXPECT_LE(static_cast<double>(bound), 1.02 * static_cast<double>(stats.bytes))
          << "bound " << bound << ", file " << stats.bytes;
    }
  }
}

TEST(GlbSize, TheWriterRefusesAFileOverTheLimitAndWritesOneAtIt) {
  test::ScratchDir dir("glb_limit");
  const GltfAnimation a = run_animation(3, 6);
  const std::string path = dir.file("run.glb");
  const GltfStats real = write_gltf_animation(path, a);
  const std::string before = slurp(path);
  // Over by one byte: refused once the JSON chunk's length is known (the buffer alone fits), and
  // over by the buffer alone: refused before tinygltf serializes. The old file stays as it was.
  for (const std::uint64_t limit :
       {std::uint64_t{real.bytes - 1}, std::uint64_t{real.buffer_bytes}}) {
    const LoweredLimit lowered(limit);
    try {
      write_gltf_animation(path, a);
      ADD_FAILURE() << "a .glb over the limit " << limit << " was written";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find("a .glb can hold"), std::string::npos) << e.what();
    }
    EXPECT_EQ(slurp(path), before);
    const std::string fresh = dir.file("fresh.glb");
    EXPECT_THROW(write_gltf_animation(fresh, a), UsageError);
    EXPECT_FALSE(fs::exists(fresh)) << "a refused .glb left a file";
  }
  for (const auto& e : fs::directory_iterator(dir.str()))
    EXPECT_TRUE(e.path().filename() == "run.glb") << "left behind: " << e.path();
  // At the limit: written whole, every length in it true.
  const LoweredLimit at(real.bytes);
  const GltfStats again = write_gltf_animation(path, a);
  EXPECT_EQ(again.bytes, real.bytes);
  const std::string glb = slurp(path);
  ASSERT_GE(glb.size(), 28u);
  const auto le32 = [&](std::size_t at) {
    return static_cast<std::uint64_t>(static_cast<unsigned char>(glb[at])) |
           static_cast<std::uint64_t>(static_cast<unsigned char>(glb[at + 1])) << 8 |
           static_cast<std::uint64_t>(static_cast<unsigned char>(glb[at + 2])) << 16 |
           static_cast<std::uint64_t>(static_cast<unsigned char>(glb[at + 3])) << 24;
  };
  EXPECT_EQ(le32(8), glb.size());
  EXPECT_EQ(20 + le32(12) + 8 + le32(20 + le32(12)), glb.size());
}

}  // namespace
}  // namespace shellcontract
