// The two exports of one run agree: every frame of the .glb (base + morph displacement) equals the
// frame sequence's file of that frame to float precision.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "export/frame_sequence_writer.hpp"
#include "export_fixtures.hpp"
#include "gltf_reader.hpp"
#include "shellcontract/export.hpp"

namespace shellcontract {
namespace {

TEST(ExportConsistency, GltfFramesEqualTheFrameSequenceToFloatPrecision) {
  test::ScratchDir dir("consistency");
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/bumpy_sphere.off");
  const Positions x = positions_from_mesh(mesh);
  const int last = 30, every = 7;
  FrameSequenceWriter sequence(dir.str(), "b", "obj", mesh, last);
  GltfAnimation a;
  a.faces = test::faces_of(mesh);
  for (int f = 0; f <= last; ++f) {
    if (f % every != 0 && f != last) continue;  // every 7th frame and the last, as the CLI will
    const Positions y = test::fake_frame(x, f, last);
    sequence.write(f, y);
    a.frame_numbers.push_back(f);
    a.frames.push_back(y);
  }
  sequence.finish();
  write_gltf_animation(dir.file("b.glb"), a);

  const tinygltf::Model m = test::load_glb(dir.file("b.glb"));
  const tinygltf::Primitive& p = m.meshes.at(0).primitives.at(0);
  ASSERT_EQ(p.targets.size() + 1, a.frames.size());
  const test::Floats base = test::read_positions(m, p.attributes.at("POSITION"));
  const double tol = 4.0 * x.cwiseAbs().maxCoeff() * std::numeric_limits<float>::epsilon();
  for (std::size_t k = 0; k < a.frames.size(); ++k) {
    test::Floats xk = base;
    if (k > 0) xk += test::read_floats(m, p.targets[k - 1].at("POSITION"));
    const Positions file =
        positions_from_mesh(read_input_mesh(sequence.file_name(a.frame_numbers[k])));
    ASSERT_EQ(file.rows(), xk.rows());
    EXPECT_LE((xk.cast<double>() - file).cwiseAbs().maxCoeff(), tol)
        << "frame " << a.frame_numbers[k];
  }
  // The frames differ from each other by much more than that: the comparison can fail.
  const Positions first = positions_from_mesh(read_input_mesh(sequence.file_name(0)));
  const Positions final = positions_from_mesh(read_input_mesh(sequence.file_name(last)));
  EXPECT_GT((final - first).cwiseAbs().maxCoeff(), 1e3 * tol);
}

}  // namespace
}  // namespace shellcontract
