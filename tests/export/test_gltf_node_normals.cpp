// Normal groups (src/mesh/normal_groups.hpp) of one mesh drawn by two nodes with different
// transforms: one node only moved, the other turned a quarter about x and stretched along its y.
// The mesh is a box whose four sides are one smooth band split at a UV seam, between flat caps
// with corners of their own (two hard edges, one seam). In each node the hard edges stay hard and
// the seam stays smooth, and the normals the file holds, brought to world space by their node's
// transform, are the area-weighted world normals at the new positions. The nodes are apart: no
// position holds copies of both.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "export/gltf_reader.hpp"
#include "export_fixtures.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/gltf_files.hpp"

namespace shellcontract {
namespace {

/// Band corners 0-9 (bottom, top, around the box; 8 and 9 repeat 0 and 1 with u = 1), then the
/// bottom cap's corners 10-13 and the top cap's 14-17, each cap with its own flat normal.
test::GltfPrimitive band_and_caps() {
  test::GltfPrimitive p;
  test::add_smooth_band_with_seam(p);
  for (const float z : {-1.0f, 1.0f}) {
    const auto first = static_cast<std::uint32_t>(p.positions.size());
    const float corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (const auto& c : corners) {
      p.positions.push_back({c[0], c[1], z});
      p.normals.push_back({0.0f, 0.0f, z});
      p.texcoords.push_back({0.5f, 0.5f});
    }
    const std::uint32_t up[6] = {0, 1, 2, 0, 2, 3}, down[6] = {0, 2, 1, 0, 3, 2};
    for (const std::uint32_t i : z > 0 ? up : down) p.indices.push_back(first + i);
  }
  return p;
}

constexpr std::size_t BAND_TRIANGLES = 8, CORNERS = 18;

/// Node k's transform, as its JSON below says: node 0 moved to x = -4; node 1 moved to x = 4,
/// turned a quarter about x and scaled by 2 along its own y (normals then turn by another map
/// than positions do).
Eigen::Affine3d node_transform(std::size_t k) {
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  if (k == 0) return t.translate(Eigen::Vector3d(-4, 0, 0));
  t.translate(Eigen::Vector3d(4, 0, 0));
  t.rotate(Eigen::Quaterniond(0.70710678, 0.70710678, 0, 0).normalized());
  t.scale(Eigen::Vector3d(1, 2, 1));
  return t;
}

/// The .glb: the mesh drawn by node 0 and node 1.
std::string two_node_glb() {
  test::GltfScene s;
  s.primitives.push_back(band_and_caps());
  s.node_transform =
      "\"translation\":[4,0,0],\"rotation\":[0.70710678,0,0,0.70710678],\"scale\":[1,2,1]";
  test::GltfParts parts = test::gltf_parts(s);
  const std::string one = "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0,";
  const std::size_t at = parts.json.find(one);
  EXPECT_NE(at, std::string::npos) << parts.json;
  parts.json.replace(at, one.size(),
                     "\"scenes\":[{\"nodes\":[0,1]}],\"nodes\":[{\"mesh\":0,\"translation\":[-4,0,"
                     "0]},{\"mesh\":0,");
  return test::glb_bytes(parts);
}

/// Node k's corners at the new positions: world positions under a map of the node's own, affine
/// so that every side stays flat while its normal turns, each side its own way.
std::vector<Eigen::Vector3d> moved_corners(const test::GltfPrimitive& p, std::size_t k) {
  Eigen::Matrix3d a;
  if (k == 0)
    a << 1.2, 0.3, 0.0, 0.0, 0.9, 0.2, 0.1, 0.0, 1.1;
  else
    a << 0.8, 0.0, 0.25, 0.2, 1.1, 0.0, 0.0, -0.3, 1.3;
  const Eigen::Affine3d t = node_transform(k);
  std::vector<Eigen::Vector3d> out;
  for (const auto& q : p.positions) {
    const Eigen::Vector3d w = t * Eigen::Vector3d(q[0], q[1], q[2]);
    out.push_back(a * (w - t.translation()) + t.translation());
  }
  return out;
}

/// Twice triangle t's area along its normal, at the corners `x`.
Eigen::Vector3d area_normal(const test::GltfPrimitive& p, const std::vector<Eigen::Vector3d>& x,
                            std::size_t t) {
  const Eigen::Vector3d &a = x[p.indices[3 * t]], &b = x[p.indices[3 * t + 1]],
                        &c = x[p.indices[3 * t + 2]];
  return (b - a).cross(c - a);
}

TEST(GltfNodeNormals, EachNodeKeepsItsHardEdgesAndSmoothSeamInWorldSpace) {
  test::ScratchDir dir("gltf_node_normals");
  const test::GltfPrimitive p = band_and_caps();
  const auto doc = parse_gltf_document("two.glb", two_node_glb(), true);
  ASSERT_EQ(doc->vertex_count(), 2 * CORNERS);
  // Simulation order: node 0's corners, then node 1's, each in accessor order.
  std::vector<Eigen::Vector3d> x[2] = {moved_corners(p, 0), moved_corners(p, 1)};
  Positions all(static_cast<Eigen::Index>(2 * CORNERS), 3);
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t v = 0; v < CORNERS; ++v)
      all.row(static_cast<Eigen::Index>(k * CORNERS + v)) = x[k][v].transpose();
  const std::string out = dir.file("out.glb");
  std::ofstream(out, std::ios::binary) << doc->text(all);
  const tinygltf::Model m = test::load_glb(out);
  ASSERT_EQ(m.nodes.size(), 2u);

  for (std::size_t k = 0; k < 2; ++k) {
    SCOPED_TRACE("node " + std::to_string(k));
    const tinygltf::Node& node = m.nodes.at(k);
    const test::Floats n = test::read_floats(
        m,
        m.meshes.at(static_cast<std::size_t>(node.mesh)).primitives.at(0).attributes.at("NORMAL"));
    ASSERT_EQ(n.rows(), static_cast<Eigen::Index>(CORNERS));
    // The file's normal in world space: by the inverse transpose of the node's transform.
    const Eigen::Matrix3d to_world = node_transform(k).linear().inverse().transpose();
    const auto world = [&](std::size_t v) {
      return Eigen::Vector3d(to_world *
                             n.row(static_cast<Eigen::Index>(v)).cast<double>().transpose())
          .normalized();
    };
    // A band corner: the area-weighted sum over the band's triangles at its position, the seam
    // copies' too, and not the caps'.
    for (std::size_t v = 0; v < 10; ++v) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (std::size_t t = 0; t < BAND_TRIANGLES; ++t)
        for (std::size_t c = 0; c < 3; ++c)
          if (p.positions[p.indices[3 * t + c]] == p.positions[v]) sum += area_normal(p, x[k], t);
      EXPECT_LT((world(v) - sum.normalized()).norm(), 1e-6)
          << "band corner " << v << ": " << world(v).transpose() << ", the band's "
          << sum.normalized().transpose();
    }
    // The seam copies: one normal, bit for bit.
    EXPECT_EQ(n.row(0), n.row(8));
    EXPECT_EQ(n.row(1), n.row(9));
    // A cap corner: its cap's own normal (the hard edge kept).
    for (std::size_t cap = 0; cap < 2; ++cap) {
      const Eigen::Vector3d want = area_normal(p, x[k], BAND_TRIANGLES + 2 * cap).normalized();
      EXPECT_LT((area_normal(p, x[k], BAND_TRIANGLES + 2 * cap + 1).normalized() - want).norm(),
                1e-12);
      for (std::size_t v = 10 + 4 * cap; v < 14 + 4 * cap; ++v)
        EXPECT_LT((world(v) - want).norm(), 1e-6)
            << "cap corner " << v << ": " << world(v).transpose() << ", the cap's "
            << want.transpose();
    }
  }
}

}  // namespace
}  // namespace shellcontract
