// Regions and strength from per-vertex weights (sim/region_weights.hpp): the file's messages
// name the line, the weighted faces' components are the regions, and the weighted force is the
// unweighted one scaled face by face.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "mesh/eigen_point_map.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/regions.hpp"
#include "sim/local_contraction.hpp"
#include "sim/region_weights.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

std::string read_error_at(const std::string& path, std::size_t vertices) {
  try {
    read_vertex_weights(path, vertices);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

std::string read_error(const std::string& text, std::size_t vertices) {
  return read_error_at(write_file("weights.txt", text), vertices);
}

TEST(RegionWeights, ReadsOneWeightPerLineSkippingCommentsAndBlanks) {
  const std::string path = write_file("good.txt", "# weights\n0\n\n0.25\n  1 \n");
  EXPECT_EQ(read_vertex_weights(path, 3), (std::vector<double>{0.0, 0.25, 1.0}));
}

TEST(RegionWeights, BadFilesAreRefusedNamingTheLine) {
  EXPECT_NE(read_error("0\n0.5\nx\n", 3).find(":3: 'x' is not a weight"), std::string::npos);
  EXPECT_NE(read_error("0\n1.5\n0\n", 3).find(":2: weight 1.5 of vertex 1 is outside [0, 1]"),
            std::string::npos);
  EXPECT_NE(read_error("0\n-0.1\n0\n", 3).find(":2:"), std::string::npos);
  EXPECT_NE(read_error("0\nnan\n0\n", 3).find(":2:"), std::string::npos);
  EXPECT_NE(read_error("0\n0 1\n0\n", 3).find(":2: '1' after the weight"), std::string::npos);
  EXPECT_NE(read_error("0\n0\n0\n# more\n1\n", 3).find(":5: more weights than the mesh's 3"),
            std::string::npos);
  EXPECT_NE(read_error("0\n0\n", 3).find("2 weights for 3 vertices (the last weight is on line 2)"),
            std::string::npos);
  EXPECT_NE(read_error("", 3).find("0 weights for 3 vertices"), std::string::npos);
  EXPECT_THROW(read_vertex_weights(::testing::TempDir() + "no/such/file", 3), InputError);
  EXPECT_THROW(check_vertex_weights({0.0, 2.0}, 2, "w"), UsageError);
  EXPECT_THROW(check_vertex_weights({0.0}, 2, "w"), UsageError);
}

// Refused by name before anything is read, as the other inputs are (read_regular_file). Before,
// a folder gave "read error after line 0", /dev/null "0 weights for 3 vertices", /dev/zero was
// read until memory ran out and a FIFO waited for a writer for ever.
TEST(RegionWeights, AFileThatIsNotARegularFileIsRefusedByName) {
  const auto error = [](const std::string& path) -> std::string {
    try {
      read_vertex_weights(path, 3);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(accepted)";
  };
  EXPECT_NE(error(::testing::TempDir()).find("it is a folder"), std::string::npos)
      << error(::testing::TempDir());
  EXPECT_NE(error("/dev/null").find("it is a device"), std::string::npos) << error("/dev/null");
}

// Review 7 (F9): "\r" line ends, alone or before "\n", end a line, as in the face list and the
// OBJ and PLY readers, and a UTF-8 byte order mark at the start is skipped. A file of lone "\r"s
// was refused as "'0.25' after the weight", the mark as "'\xEF\xBB\xBF0.5' is not a weight".
TEST(RegionWeights, CarriageReturnLineEndsAndAByteOrderMarkAreRead) {
  const std::vector<double> expected{0.0, 0.25, 1.0};
  EXPECT_EQ(read_vertex_weights(write_file("cr.txt", "0\r0.25\r1\r"), 3), expected);
  EXPECT_EQ(read_vertex_weights(write_file("mixed.txt", "# w\r0\r\n0.25\n\r1"), 3), expected);
  EXPECT_EQ(read_vertex_weights(write_file("bom.txt",
                                           "\xEF\xBB\xBF"
                                           "0\r\n0.25\r\n1\r\n"),
                                3),
            expected);
  EXPECT_NE(read_error("0\r0.5\rx\r", 3).find(":3: 'x' is not a weight"), std::string::npos);
}

// Review 7 (F6): a file larger than a weights file of the mesh can need (a wrong file, a huge
// sparse one) is refused by its size, naming it, before it is read. It was read whole and copied:
// 1 GB cost 4 GB before its first line was refused, and a larger one ended in "out of memory",
// naming no file. (The file here is sparse: it takes no disk.)
TEST(RegionWeights, AFileLargerThanTheMeshCanNeedIsRefusedUnread) {
  const std::string path = write_file("huge.txt", "0.5\n");
  std::filesystem::resize_file(path, std::uint64_t{1} << 40);
  const std::string why = read_error_at(path, 3);
  std::filesystem::remove(path);
  EXPECT_NE(why.find(path + ": file too large: 1099511627776 bytes, more than the"),
            std::string::npos)
      << why;
}

TEST(RegionWeights, WeightedFacesMakeOneRegionPerComponent) {
  Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/ico2.off");
  const Positions x = positions_from_mesh(mesh);
  // Two caps at opposite ends of the x axis: two regions; everything else weight 0.
  std::vector<double> w(mesh.number_of_vertices(), 0.0);
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    if (std::abs(x(i, 0)) > 0.8 * x.col(0).cwiseAbs().maxCoeff()) w[static_cast<std::size_t>(i)] = 0.6;
  EXPECT_EQ(mark_weighted_regions(mesh, w), 2u);
  const std::vector<int> region = stored_regions(mesh);
  const std::vector<double> face_weight = stored_region_weights(mesh);
  const std::vector<double> expected = face_weights(mesh, w);
  ASSERT_EQ(face_weight.size(), mesh.number_of_faces());
  for (FaceIndex f : mesh.faces()) {
    double mean = 0.0;
    for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) mean += w[v.idx()] / 3;
    EXPECT_NEAR(face_weight[f.idx()], mean, 1e-15);
    EXPECT_EQ(face_weight[f.idx()], expected[f.idx()]);
    // Weight 0 is outside; every weighted face is in a region.
    EXPECT_EQ(region[f.idx()] >= 0, mean > 0.0) << f.idx();
  }
  // The two caps lie on opposite sides: no face of region 0 has x of the other sign than another.
  std::vector<int> sign(2, 0);
  for (FaceIndex f : mesh.faces()) {
    if (region[f.idx()] < 0) continue;
    const int s = x(mesh.target(mesh.halfedge(f)).idx(), 0) > 0 ? 1 : -1;
    int& seen = sign[static_cast<std::size_t>(region[f.idx()])];
    if (seen == 0) seen = s;
    EXPECT_EQ(seen, s);
  }
  EXPECT_NE(sign[0], sign[1]);
}

TEST(RegionWeights, WeightedForceIsTheUnweightedOneScaledByFace) {
  Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/ico2.off");
  const Positions x = positions_from_mesh(mesh);
  Faces faces(static_cast<Eigen::Index>(mesh.number_of_faces()), 3);
  for (FaceIndex f : mesh.faces()) {
    int k = 0;
    for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      faces(f.idx(), k++) = static_cast<int>(v.idx());
  }
  const Faces region = faces.topRows(30);
  const Eigen::VectorXd inv_mass = Eigen::VectorXd::Ones(x.rows());
  Positions plain, ones, twice, zero;
  local_contraction_forces(x, region, 3.0, inv_mass, plain);
  local_contraction_forces(x, region, 3.0, Eigen::VectorXd::Ones(30), inv_mass, ones);
  local_contraction_forces(x, region, 1.5, Eigen::VectorXd::Constant(30, 2.0), inv_mass, twice);
  local_contraction_forces(x, region, 3.0, Eigen::VectorXd::Zero(30), inv_mass, zero);
  EXPECT_LE((plain - ones).cwiseAbs().maxCoeff(), 1e-12 * plain.cwiseAbs().maxCoeff());
  EXPECT_LE((plain - twice).cwiseAbs().maxCoeff(), 1e-12 * plain.cwiseAbs().maxCoeff());
  EXPECT_EQ(zero.cwiseAbs().maxCoeff(), 0.0);
  // Half the faces at weight 0.5: no net force (the rigid-body part removed) and a field that
  // differs from the uniform one.
  Eigen::VectorXd mixed = Eigen::VectorXd::Ones(30);
  mixed.head(15).setConstant(0.5);
  Positions f;
  local_contraction_forces(x, region, 3.0, mixed, inv_mass, f);
  EXPECT_LE(f.colwise().sum().norm(), 1e-12 * f.cwiseAbs().maxCoeff());
  EXPECT_GT((f - plain).cwiseAbs().maxCoeff(), 1e-3 * plain.cwiseAbs().maxCoeff());
}

TEST(RegionWeights, RegionMeanIsAreaWeighted) {
  // Two triangles in the plane z = 0 of areas 1/2 and 2 (closed form): weights 1 and 0 give
  // 0.5 / 2.5 = 0.2; one weight everywhere gives that weight; no weights give 1.
  Positions x(5, 3);
  x << 0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 0, 2, 0;
  Faces faces(2, 3);
  faces << 0, 1, 2, 0, 3, 4;
  EXPECT_NEAR(mean_region_weight(x, faces, {0, 1}, {1.0, 0.0}), 0.2, 1e-15);
  EXPECT_NEAR(mean_region_weight(x, faces, {0, 1}, {0.3, 0.3}), 0.3, 1e-15);
  EXPECT_EQ(mean_region_weight(x, faces, {0, 1}, {}), 1.0);
}

}  // namespace
}  // namespace shellcontract
