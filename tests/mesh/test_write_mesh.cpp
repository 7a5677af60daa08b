// mesh_for_output / write_ply_atomic: the one PLY writer (CGAL's Surface_mesh writer) keeps the
// attached property maps and every double bitwise. The plain formats' round trip is in
// test_io.cpp (RoundTrip).
#include <gtest/gtest.h>

#include <CGAL/IO/Color.h>
#include <CGAL/IO/OFF.h>
#include <CGAL/Surface_mesh/IO/PLY.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>

#include <unistd.h>

#include "mesh/eigen_point_map.hpp"
#include "mesh/properties.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

std::string temp_file(const std::string& name) {
  return (fs::temp_directory_path() / ("shellcontract_test_write_" + std::to_string(::getpid()) + "_" + name)).string();
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// Values that need all 17 significant digits (15 would change them).
double awkward(std::size_t i) { return 1.0 / 3.0 + 1e-3 * std::sin(std::sqrt(2.0) * static_cast<double>(i)); }

class PlyWithProperties : public ::testing::Test {
 protected:
  void SetUp() override {
    mesh_ = read_input_mesh(std::string(test::MESH_DIR) + "/ico2.off");
    x_ = positions_from_mesh(mesh_);
    for (Eigen::Index i = 0; i < x_.rows(); ++i)
      for (int k = 0; k < 3; ++k) x_(i, k) *= 1.0 + 1e-3 * awkward(static_cast<std::size_t>(3 * i + k));
    std::ostringstream s15;
    s15 << std::setprecision(15) << awkward(1);
    ASSERT_NE(std::stod(s15.str()), awkward(1)) << "the values must need 17 digits, or the test could not fail";
  }
  Mesh mesh_;
  Positions x_;
};

TEST_F(PlyWithProperties, RoundTripKeepsMapsAndDoublesBitwise) {
  Mesh out = mesh_for_output(mesh_, x_);
  auto region = property::add_map<FaceIndex, int>(out, property::REGION, -1);
  auto colour = property::add_map<FaceIndex, CGAL::IO::Color>(out, property::FACE_COLOR);
  auto H = property::add_map<VertexIndex, double>(out, property::MEAN_CURVATURE);
  for (FaceIndex f : out.faces()) {
    region[f] = f.idx() % 3 == 0 ? -1 : static_cast<int>(f.idx() % 7);
    colour[f] = CGAL::IO::Color(static_cast<unsigned char>(f.idx() % 256), 1, 2);
  }
  for (VertexIndex v : out.vertices()) H[v] = awkward(v.idx()) - 5.0;
  const std::string path = temp_file("props.ply");
  write_ply_atomic(path, out, "two\nlines");
  const std::string text = read_text(path);
  EXPECT_NE(text.find("format ascii 1.0"), std::string::npos) << text.substr(0, 400);
  EXPECT_NE(text.find("comment two\ncomment lines\n"), std::string::npos) << text.substr(0, 400);
  EXPECT_NE(text.find("property double mean_curvature"), std::string::npos);
  EXPECT_NE(text.find("property int region"), std::string::npos);
  EXPECT_NE(text.find("property uchar red"), std::string::npos);

  // Our reader (what `check` and `run` use) gives the positions and faces back exactly.
  const Mesh back = read_input_mesh(path);
  const Positions y = positions_from_mesh(back);
  ASSERT_EQ(y.rows(), x_.rows());
  for (Eigen::Index i = 0; i < x_.rows(); ++i)
    for (int k = 0; k < 3; ++k) ASSERT_EQ(y(i, k), x_(i, k)) << "vertex " << i << " coordinate " << k;

  // CGAL's reader (on a file CGAL wrote) gives the property maps back exactly.
  Mesh cgal;
  std::ifstream in(path);
  ASSERT_TRUE(CGAL::IO::read_PLY(in, cgal));
  fs::remove(path);
  ASSERT_EQ(cgal.number_of_faces(), out.number_of_faces());
  const auto region_back = property::get_map<FaceIndex, int>(cgal, property::REGION);
  const auto H_back = property::get_map<VertexIndex, double>(cgal, property::MEAN_CURVATURE);
  const auto colour_back = property::get_map<FaceIndex, CGAL::IO::Color>(cgal, property::FACE_COLOR);
  for (FaceIndex f : out.faces()) {
    EXPECT_EQ(region_back[f], region[f]) << "face " << f.idx();
    EXPECT_EQ(colour_back[f].red(), colour[f].red()) << "face " << f.idx();
  }
  for (VertexIndex v : out.vertices()) ASSERT_EQ(H_back[v], H[v]) << "vertex " << v.idx();  // bitwise
}

TEST_F(PlyWithProperties, MeshForOutputDropsTheMapsAndKeepsCorners) {
  property::add_map<VertexIndex, double>(mesh_, property::INV_MASS, 1.0);
  const Mesh out = mesh_for_output(mesh_, x_);
  EXPECT_FALSE((out.property_map<VertexIndex, double>(property::INV_MASS).second));
  const std::string path = temp_file("plain.ply");
  write_mesh_atomic(path, mesh_, x_);
  const std::string text = read_text(path);
  fs::remove(path);
  EXPECT_EQ(text.find("inv_mass"), std::string::npos) << "a rest-state map leaked into the file";
  for (FaceIndex f : mesh_.faces()) {
    ASSERT_EQ(mesh_.target(mesh_.halfedge(f)), out.target(out.halfedge(f))) << "face " << f.idx();
  }
  for (VertexIndex v : out.vertices())
    ASSERT_EQ(out.point(v), Point3(x_(v.idx(), 0), x_(v.idx(), 1), x_(v.idx(), 2)));
  EXPECT_THROW(mesh_for_output(mesh_, x_.topRows(3)), std::invalid_argument);
}

// Before: a NaN was written as "nan" (OFF, OBJ, PLY) into a file that no reader takes back.
TEST_F(PlyWithProperties, PositionsThatAreNotFiniteAreRefusedAndNothingIsWritten) {
  for (const double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL})
    for (const char* ext : {"off", "obj", "ply", "stl"}) {
      Positions x = x_;
      x(2, 1) = bad;
      const std::string path = temp_file(std::string("not_finite.") + ext);
      try {
        write_mesh_atomic(path, mesh_, x);
        ADD_FAILURE() << ext << ": written";
      } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("vertex 2"), std::string::npos) << e.what();
      }
      EXPECT_FALSE(fs::exists(path)) << ext;
    }
}

TEST_F(PlyWithProperties, FilesHoldExactlyWhatCgalWritesAtSeventeenDigits) {
  // write_atomic formats doubles with to_chars instead of the stream's printf; the bytes must
  // be those of CGAL's writer on a plain stream at precision 17.
  Mesh out = mesh_for_output(mesh_, x_);
  auto H = property::add_map<VertexIndex, double>(out, property::MEAN_CURVATURE);
  auto P = property::add_map<VertexIndex, float>(out, property::PRESSURE_LOAD);
  for (VertexIndex v : out.vertices()) {
    H[v] = -awkward(v.idx()) * 1e-300;  // a subnormal-range exponent too
    P[v] = static_cast<float>(awkward(v.idx()));
  }
  const auto np = CGAL::parameters::stream_precision(17);
  std::ostringstream expected_ply;
  ASSERT_TRUE(CGAL::IO::write_PLY(expected_ply, out, "c", np));
  const std::string ply = temp_file("exact.ply");
  write_ply_atomic(ply, out, "c");
  EXPECT_EQ(read_text(ply), expected_ply.str());
  fs::remove(ply);

  std::ostringstream expected_off;
  ASSERT_TRUE(CGAL::IO::write_OFF(expected_off, mesh_, np.vertex_point_map(EigenPointMap(x_))));
  const std::string off = temp_file("exact.off");
  write_mesh_atomic(off, mesh_, x_);
  EXPECT_EQ(read_text(off), expected_off.str());
  fs::remove(off);
}

}  // namespace
}  // namespace shellcontract
