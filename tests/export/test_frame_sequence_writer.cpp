// FrameSequenceWriter: file names, contents read back, statistics, errors from the writer thread.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "export/frame_sequence_writer.hpp"
#include "export_fixtures.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

TEST(FrameFileName, PadsToTheDigitsOfTheLargestFrame) {
  EXPECT_EQ(frame_file_name("out", "bear", "off", 5, 300), "out/bear_005.off");
  EXPECT_EQ(frame_file_name("out", "bear", "off", 300, 300), "out/bear_300.off");
  EXPECT_EQ(frame_file_name("", "b", "ply", 7, 9), "b_7.ply");
  EXPECT_EQ(frame_file_name("d", "b", "stl", 0, 1000), "d/b_0000.stl");
  EXPECT_THROW(frame_file_name("d", "b", "stl", 11, 10), std::invalid_argument);
}

class FrameSequenceWriterTest : public ::testing::TestWithParam<std::string> {};

TEST_P(FrameSequenceWriterTest, WritesEveryQueuedFrameWithItsPositions) {
  const std::string ext = GetParam();
  test::ScratchDir dir("seq_" + ext);
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/ico2.off");
  const Positions x = positions_from_mesh(mesh);
  const std::vector<int> frames{0, 5, 10, 15, 20, 23};
  {
    // Capacity 1: write() has to wait for the writer, which exercises the queue's hand-over.
    FrameSequenceWriter writer(dir.str(), "ico", ext, mesh, 23, 1);
    for (int f : frames) writer.write(f, test::fake_frame(x, f, 23));
    writer.finish();
    const ExportStats s = writer.stats();
    EXPECT_EQ(s.frames_written, static_cast<int>(frames.size()));
    std::uintmax_t bytes = 0;
    for (const auto& e : fs::directory_iterator(dir.str())) bytes += e.file_size();
    EXPECT_EQ(s.bytes, bytes);
  }
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.str())) ++files;
  EXPECT_EQ(files, frames.size()) << "only the frames' files, no temporary left over";
  for (int f : frames) {
    const std::string path = frame_file_name(dir.str(), "ico", ext, f, 23);
    ASSERT_TRUE(fs::exists(path)) << path;
    const Mesh back = read_input_mesh(path);
    const Positions y = positions_from_mesh(back);
    const Positions expected = test::fake_frame(x, f, 23);
    ASSERT_EQ(y.rows(), expected.rows()) << path;
    // Compared corner by corner: STL has no shared vertices, so a reader may number them in
    // another order (the faces keep theirs).
    const Faces fy = test::faces_of(back), fx = test::faces_of(mesh);
    ASSERT_EQ(fy.rows(), fx.rows()) << path;
    double err = 0.0;
    for (Eigen::Index j = 0; j < fx.rows(); ++j)
      for (int k = 0; k < 3; ++k)
        err = std::max(err, (y.row(fy(j, k)) - expected.row(fx(j, k))).cwiseAbs().maxCoeff());
    EXPECT_LE(err, 1e-14) << path;  // 17 significant digits
  }
}

INSTANTIATE_TEST_SUITE_P(Formats, FrameSequenceWriterTest,
                         ::testing::Values("off", "obj", "ply", "stl"));

TEST(FrameSequenceWriter, SameFramesGiveByteIdenticalFiles) {
  test::ScratchDir a("same_a"), b("same_b");
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/ico1.off");
  const Positions x = positions_from_mesh(mesh);
  for (const auto* dir : {&a, &b}) {
    FrameSequenceWriter writer(dir->str(), "m", "off", mesh, 3, dir == &a ? 1 : 8);
    for (int f = 0; f <= 3; ++f) writer.write(f, test::fake_frame(x, f, 3));
    writer.finish();
  }
  for (int f = 0; f <= 3; ++f) {
    std::ifstream fa(frame_file_name(a.str(), "m", "off", f, 3)),
        fb(frame_file_name(b.str(), "m", "off", f, 3));
    const std::string sa((std::istreambuf_iterator<char>(fa)), {}),
        sb((std::istreambuf_iterator<char>(fb)), {});
    EXPECT_FALSE(sa.empty());
    EXPECT_EQ(sa, sb) << "frame " << f;
  }
}

TEST(FrameSequenceWriter, CallerCanChangeItsPositionsRightAfterWrite) {
  test::ScratchDir dir("copy");
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/ico1.off");
  Positions x = positions_from_mesh(mesh);
  const Positions original = x;
  FrameSequenceWriter writer(dir.str(), "m", "off", mesh, 1);
  writer.write(0, x);
  x.setConstant(1e9);  // the simulation moves on; the queued copy must not see it
  writer.write(1, x);
  writer.finish();
  const Positions back =
      positions_from_mesh(read_input_mesh(frame_file_name(dir.str(), "m", "off", 0, 1)));
  EXPECT_LE((back - original).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(FrameSequenceWriter, UnwritableFolderSurfacesFromFinish) {
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/ico1.off");
  const Positions x = positions_from_mesh(mesh);
  FrameSequenceWriter writer("/nonexistent_shellcontract_dir/sub", "m", "off", mesh, 10);
  EXPECT_NO_THROW(writer.write(0, x));
  EXPECT_NO_THROW(writer.write(1, x));
  EXPECT_THROW(writer.finish(), UsageError);
  EXPECT_EQ(writer.stats().frames_written, 0);
  EXPECT_NO_THROW(writer.finish()) << "the error is reported once";
}

TEST(FrameSequenceWriter, RejectsBadArguments) {
  test::ScratchDir dir("bad");
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/ico1.off");
  EXPECT_THROW(FrameSequenceWriter(dir.str(), "m", "gltf", mesh, 3), UsageError);
  FrameSequenceWriter writer(dir.str(), "m", ".OFF", mesh, 3);
  EXPECT_EQ(writer.file_name(2), dir.str() + "/m_2.off");
  EXPECT_THROW(writer.write(0, Positions::Zero(3, 3)), std::invalid_argument);
  EXPECT_THROW(writer.write(4, positions_from_mesh(mesh)), std::invalid_argument);
  writer.finish();
  EXPECT_THROW(writer.write(1, positions_from_mesh(mesh)), std::invalid_argument);
}

}  // namespace
}  // namespace shellcontract
