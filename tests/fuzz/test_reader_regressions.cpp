// Every input that crashed or misled the reader, kept as a named file under
// tests/data/fuzz/regressions, and the scale range 1e-150 .. 1e150.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/eigen_point_map.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/cli_runner.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

std::string regression(const std::string& name) { return std::string(SHELLCONTRACT_FUZZ_DATA_DIR) + "/regressions/" + name; }

/// Reads `path`, expecting an InputError that names the file and contains each of `parts`.
void expect_refused(const std::string& path, const std::vector<std::string>& parts) {
  try {
    read_input_mesh(path);
    ADD_FAILURE() << path << " was accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << "message does not name the file: " << msg;
    for (const std::string& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "missing '" << p << "' in: " << msg;
  }
}

/// The unit tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1) of the regression files.
void expect_unit_tetrahedron(const std::string& path) {
  try {
    InputReport report;
    const Mesh mesh = read_input_mesh(path, &report);
    ASSERT_EQ(mesh.number_of_vertices(), 4u) << path;
    ASSERT_EQ(mesh.number_of_faces(), 4u) << path;
    const Positions x = positions_from_mesh(mesh);
    Positions expected(4, 3);
    expected << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
    EXPECT_EQ(x, expected) << path;
    EXPECT_NEAR(report.volume, 1.0 / 6.0, 1e-15) << path;
  } catch (const std::exception& e) {
    ADD_FAILURE() << path << " (a legal file) was refused: " << e.what();
  }
}

// Every file of the folder (also those found by the fuzzer, kept without a test of their own):
// read as a mesh or refused with an InputError naming the file, nothing else.
TEST(ReaderRegression, EveryRegressionFileIsReadOrRefusedCleanly) {
  std::size_t n = 0;
  for (const auto& entry : fs::directory_iterator(std::string(SHELLCONTRACT_FUZZ_DATA_DIR) + "/regressions")) {
    const std::string path = entry.path().string();
    ++n;
    try {
      read_input_mesh(path);
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << path << ": " << typeid(e).name() << ": " << e.what();
    }
  }
  EXPECT_GE(n, 14u);
}

// CGAL 5.5's PLY reader segfaults on integer-typed coordinates (a null PLY_read_typed_number).
TEST(ReaderRegression, PlyIntegerCoordinatesAreRead) {
  expect_unit_tetrahedron(regression("ply_int_coordinates.ply"));
  expect_unit_tetrahedron(regression("ply_uchar_coordinates.ply"));
}

// CGAL 5.5's PLY reader calls back() on its empty element list (segfault).
TEST(ReaderRegression, PlyPropertyBeforeElementIsAParseError) {
  expect_refused(regression("ply_property_before_element.ply"), {"parse error", "line 3", "property", "element"});
}

// CGAL 5.5's PLY reader spends minutes and gigabytes on a count the file cannot hold.
TEST(ReaderRegression, PlyHugeDeclaredCountIsBoundedByTheFileSize) {
  expect_refused(regression("ply_huge_vertex_count.ply"), {"truncated file", "1000000000"});
  // 58 bytes: 10^9 vertices without properties kept CGAL busy for seconds and gigabytes.
  expect_refused(regression("ply_vertex_count_without_properties.ply"), {"parse error", "line 3", "1000000000 declared", "x, y, z"});
}

// An element without properties takes no bytes, so no body can bound its count: the PLY document
// then walked 2^53 - 1 empty instances (months) after read_ply had accepted the file. A count
// beyond the file's bytes is refused by the reader and by the header the document reads.
TEST(ReaderRegression, PlyElementWithoutPropertiesCountsAtMostTheFileSize) {
  const std::string path = regression("ply_element_without_properties_huge_count.ply");
  expect_refused(path, {"implausible count", "element 'junk' (line 9)",
                        "9007199254740991 instances", "240 bytes"});
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(bytes.size(), 240u);
  try {
    (void)parse_ply_document(path, bytes);
    ADD_FAILURE() << "the PLY document took the file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": implausible count: element 'junk'"),
              std::string::npos)
        << e.what();
  }
}

// std::bad_alloc from a reserve of the declared count (ours; CGAL's OFF reader resizes to it).
TEST(ReaderRegression, OffHugeDeclaredCountsAreTruncatedFiles) {
  expect_refused(regression("off_huge_vertex_count.off"), {"truncated file", "1000000000000 vertices"});
  expect_refused(regression("off_huge_face_count.off"), {"truncated file", "1000000000000000000 faces"});
  // A count that fits CGAL's int: CGAL's reader resized its arrays to it (std::bad_alloc).
  expect_refused(regression("off_vertex_count_fits_int.off"), {"truncated file", "2000000000 vertices"});
}

// CGAL 5.5's OFF header reader doubles the (unused) edge count in an int: a signed overflow
// beyond INT_MAX / 2, found by UBSan (scripts/sanitize.sh). Refused with a reason instead.
TEST(ReaderRegression, OffEdgeCountBeyondCgalsIntIsRefused) {
  expect_refused(regression("off_edge_count_overflows_int.off"), {"parse error", "edge count 2147483647"});
}

// A UTF-8 byte-order mark and classic-Mac line ends are legal text: read, not misreported.
TEST(ReaderRegression, OffWithByteOrderMarkOrCrLineEndsIsRead) {
  expect_unit_tetrahedron(regression("off_utf8_bom.off"));
  expect_unit_tetrahedron(regression("off_cr_line_ends.off"));
}

// CGAL 5.5's polygon-soup OFF reader does not skip a binary face's colour count: every face
// after the first was misread ("face 1 has 0 vertices").
TEST(ReaderRegression, BinaryOffIsRead) { expect_unit_tetrahedron(regression("off_binary_tetrahedron.off")); }

// The open boundary is the more fundamental problem than the unused vertex.
TEST(ReaderRegression, OpenMeshWithUnusedVertexIsReportedAsOpen) {
  expect_refused(regression("off_open_with_unused_vertex.off"), {"open boundary"});
}

// STL has no vertex numbers: a refusal names facets and points, never "vertex N".
TEST(ReaderRegression, StlRefusalNamesFacetsAndPointsNotVertexNumbers) {
  const std::string path = regression("stl_one_facet.stl");
  expect_refused(path, {"open boundary", "facet 0", "(0, 0, 0)"});
  try {
    read_input_mesh(path);
  } catch (const InputError& e) {
    EXPECT_FALSE(std::regex_search(std::string(e.what()), std::regex("vertex [0-9]"))) << e.what();
  }
}

// `run` used to refuse these after `check` called them usable; now the reader refuses them.
TEST(ReaderRegression, ZeroVolumeAndZeroDiagonalAreRefusedByTheReader) {
  expect_refused(regression("off_zero_volume.off"), {"no positive volume"});
  const std::string dir = fs::temp_directory_path() / ("shellcontract_regression_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir + "/point.off") << "OFF\n4 4 0\n1 1 1\n1 1 1\n1 1 1\n1 1 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  expect_refused(dir + "/point.off", {"zero bounding-box diagonal"});
  fs::remove_all(dir);
}

// 400 oriented points on the unit sphere: CGAL's poisson_surface_reconstruction_delaunay
// segfaulted (facets_in_complex_2_to_triangle_mesh on an empty complex); `reconstruct` must
// exit 0 or 2, and write nothing on 2. Bad point files are refused with exit 2 too.
TEST(ReaderRegression, ReconstructExitsZeroOrTwo) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << "needs the CLI";
  const std::string dir = fs::temp_directory_path() / ("shellcontract_reconstruct_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ostringstream xyz;
  xyz << std::setprecision(17);
  const int n = 400;
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z), t = 2.399963 * i;
    for (int k = 0; k < 2; ++k) xyz << r * std::cos(t) << ' ' << r * std::sin(t) << ' ' << z << (k ? '\n' : ' ');
  }
  std::ofstream(dir + "/sphere.xyz") << xyz.str();
  for (const std::string& in : {dir + "/sphere.xyz", regression("ply_property_before_element.ply"),
                                regression("ply_int_coordinates.ply"), regression("off_vertex_count_fits_int.off")}) {
    const std::string out = dir + "/out.off";
    const test::RunResult r = test::run_cli({"reconstruct", in, "-o", out});
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 2) << in << " exited " << r.exit_code << "\n" << r.output;
    if (r.exit_code == 2) {
      EXPECT_FALSE(fs::exists(out)) << in;
      EXPECT_NE(r.output.find(in), std::string::npos) << r.output;
    }
    fs::remove(out);
  }
  fs::remove_all(dir);
}

/// Writes the OFF file meshes/NAME with every coordinate multiplied by `s` (17 significant
/// digits), keeping its polygons as they are.
void write_scaled(const std::string& name, double s, const std::string& out) {
  std::ifstream in(std::string(test::MESH_DIR) + "/" + name);
  std::vector<std::string> tokens;
  for (std::string line; std::getline(in, line);) {
    std::istringstream ls(line.substr(0, line.find('#')));
    for (std::string t; ls >> t;) tokens.push_back(t);
  }
  ASSERT_GE(tokens.size(), 4u);
  ASSERT_EQ(tokens[0], "OFF");
  const std::size_t nv = std::stoul(tokens[1]);
  std::ostringstream o;
  o << std::setprecision(17) << "OFF\n" << tokens[1] << ' ' << tokens[2] << ' ' << tokens[3] << '\n';
  for (std::size_t i = 0; i < 3 * nv; ++i) o << std::stod(tokens[4 + i]) * s << ((i % 3 == 2) ? '\n' : ' ');
  for (std::size_t i = 4 + 3 * nv; i < tokens.size();) {  // one face per line, as OFF wants
    const std::size_t n = std::stoul(tokens[i]);
    for (std::size_t k = 0; k <= n && i < tokens.size(); ++k) o << tokens[i++] << (k == n ? '\n' : ' ');
  }
  std::ofstream(out) << o.str();
}

// Volumes, areas and the zero-area test are computed on the normalized mesh: at 1e140 the cubes
// overflowed (volume -nan, "inside-out") and at 1e-100 every face was called zero-area.
TEST(ReaderRegression, ScaledMeshesFrom1em150To1e150GiveTheSameReport) {
  const std::string dir = fs::temp_directory_path() / ("shellcontract_scaled_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  for (const char* name : {"bumpy_sphere.off", "cube_quads.off", "torus.off"}) {
    InputReport ref;
    read_input_mesh(std::string(test::MESH_DIR) + "/" + name, &ref);
    for (double s : {1e-150, 1e-100, 1e100, 1e140, 1e150}) {
      const std::string path = dir + "/scaled.off";
      write_scaled(name, s, path);
      InputReport r;
      try {
        read_input_mesh(path, &r);
      } catch (const std::exception& e) {
        ADD_FAILURE() << name << " scaled by " << s << " refused: " << e.what();
        continue;
      }
      EXPECT_EQ(r.faces, ref.faces) << name << " x " << s;
      EXPECT_EQ(r.reoriented, ref.reoriented) << name << " x " << s;
      EXPECT_EQ(r.zero_area_faces, ref.zero_area_faces) << name << " x " << s;
      EXPECT_EQ(r.triangulated_faces, ref.triangulated_faces) << name << " x " << s;
      // The volume in input units overflows a double above about 1e102 (s^3); below, it scales.
      if (std::isfinite(ref.volume * s * s * s) && ref.volume * s * s * s > 0.0) {
        EXPECT_NEAR(r.volume / (ref.volume * s * s * s), 1.0, 1e-12) << name << " x " << s;
      }
      if (!fs::exists(SHELLCONTRACT_CLI_PATH)) continue;
      // check and run agree: both accept.
      const test::RunResult c = test::run_cli({"check", path});
      EXPECT_EQ(c.exit_code, 0) << name << " x " << s << "\n" << c.output;
      EXPECT_EQ(c.output.find("inside-out"), std::string::npos) << c.output;
    }
  }
  fs::remove_all(dir);
}

// The paper's eight at the two scales of the issue, through check and run.
TEST(ReaderRegression, EightScaled1e140And1em100IsAcceptedByCheckAndRun) {
  const std::string eight = std::string(test::PAPER_MESH_DIR) + "/eight.off";
  if (!fs::exists(eight) || !fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << "needs " << eight << " and the CLI";
  const std::string dir = fs::temp_directory_path() / ("shellcontract_eight_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const Mesh mesh = read_input_mesh(eight);
  for (double s : {1e140, 1e-100}) {
    const std::string path = dir + "/eight.off";
    write_mesh_atomic(path, mesh, positions_from_mesh(mesh) * s);
    const test::RunResult c = test::run_cli({"check", path});
    EXPECT_EQ(c.exit_code, 0) << s << "\n" << c.output;
    EXPECT_NE(c.output.find("zero_area_faces: 0\n"), std::string::npos) << s << "\n" << c.output;
    EXPECT_NE(c.output.find("reoriented: no\n"), std::string::npos) << s << "\n" << c.output;
    const test::RunResult r = test::run_cli({"run", path, "-o", dir + "/out.off", "--frames", "2", "--quiet"});
    EXPECT_EQ(r.exit_code, 0) << s << "\n" << r.output;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace shellcontract
