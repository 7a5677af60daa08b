// Spherical-region selection against known bump faces (meshes/bumpy_sphere.bumps.txt, written
// by scripts/make_meshes.py from the construction, not by this code), the plain-sphere decision,
// scale invariance, and the region face-list file format.
#include <gtest/gtest.h>
#include <stdlib.h>  // setenv, unsetenv
#include <unistd.h>  // getpid: one temporary folder per test process

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/curvature.hpp"
#include "mesh/eigen_point_map.hpp"
#include "mesh/properties.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/regions.hpp"
#include "support/cgal_mesh.hpp"
#include "support/mesh_fixtures.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

std::string mesh_path(const std::string& name) { return std::string(test::MESH_DIR) + "/" + name; }

/// A fresh path in the test's temporary folder.
std::string temp_path(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("shellcontract_test_regions_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

void write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

/// Faces sharing at least a vertex with `faces`, including them.
std::set<int> with_vertex_neighbours(const Mesh& mesh, const std::vector<int>& faces) {
  std::set<int> out;
  for (int f : faces)
    for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(FaceIndex(f)), mesh))
      for (FaceIndex g : CGAL::faces_around_target(mesh.halfedge(v), mesh)) out.insert(static_cast<int>(g.idx()));
  return out;
}

class BumpySphere : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(fs::exists(mesh_path("bumpy_sphere.off"))) << "meshes/bumpy_sphere.off is part of the repository";
    mesh_ = read_input_mesh(mesh_path("bumpy_sphere.off"));
    x_ = positions_from_mesh(mesh_);
    bumps_ = read_region_file(mesh_path("bumpy_sphere.bumps.txt"), mesh_.number_of_faces());
  }
  Mesh mesh_;
  Positions x_;
  std::vector<std::vector<int>> bumps_;
};

TEST_F(BumpySphere, SidecarHasTheFaceCountsOfTheReadme) {
  ASSERT_EQ(bumps_.size(), 3u);
  EXPECT_EQ(bumps_[0].size(), 88u);
  EXPECT_EQ(bumps_[1].size(), 45u);
  EXPECT_EQ(bumps_[2].size(), 19u);
}

// The finder's stage times go to the caller's report, in stage order, and the library prints
// nothing (it used to print them on stderr when an environment variable was set: a host program
// embedding the library must not have its stderr written by a variable it did not set).
TEST_F(BumpySphere, StageTimesGoToTheReportAndNothingIsPrinted) {
  ASSERT_EQ(::setenv("SC_REGION_TIMING", "1", 1), 0);
  RegionReport report;
  ::testing::internal::CaptureStderr();
  const auto t0 = std::chrono::steady_clock::now();
  select_spherical_regions(mesh_, x_, RegionOptions{}, &report);
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string printed = ::testing::internal::GetCapturedStderr();
  ::unsetenv("SC_REGION_TIMING");
  EXPECT_EQ(printed, "");
  std::vector<std::string> stages;
  double wall = 0.0;
  for (const RegionStageTime& t : report.stage_times) {
    stages.push_back(t.stage);
    wall += t.wall_s;
  }
  EXPECT_EQ(stages, (std::vector<std::string>{"curvature", "smoothing", "free growth",
                                              "ranked growth", "parts", "shape"}));
  // The laps partition one stretch of the call: together no longer than the call.
  EXPECT_LE(wall, elapsed);
  // The parts method reports its cap finder's stages, the tip finder none.
  RegionOptions parts;
  parts.method = RegionMethod::Parts;
  select_spherical_regions(mesh_, x_, parts, &report);
  EXPECT_EQ(report.stage_times.size(), 6u);
  RegionOptions tips;
  tips.method = RegionMethod::Tips;
  select_spherical_regions(mesh_, x_, tips, &report);
  EXPECT_TRUE(report.stage_times.empty());
}

TEST_F(BumpySphere, EachBumpIsRecoveredAndNothingElse) {
  RegionReport report;
  const std::vector<int> region = select_spherical_regions(mesh_, x_, RegionOptions{}, &report);
  ASSERT_EQ(region.size(), mesh_.number_of_faces());
  ASSERT_EQ(report.regions.size(), 3u) << "one region per bump";

  std::set<int> matched_ids;
  std::set<int> allowed;  // the bumps and the one band of faces that straddle their rims
  for (std::size_t b = 0; b < bumps_.size(); ++b) {
    const std::set<int> truth(bumps_[b].begin(), bumps_[b].end());
    // The region with the most faces on this bump.
    std::vector<int> overlap(report.regions.size(), 0);
    for (int f : bumps_[b])
      if (region[static_cast<std::size_t>(f)] >= 0) ++overlap[static_cast<std::size_t>(region[static_cast<std::size_t>(f)])];
    const int id = static_cast<int>(std::max_element(overlap.begin(), overlap.end()) - overlap.begin());
    std::size_t intersection = 0, uni = truth.size();
    for (std::size_t f = 0; f < region.size(); ++f)
      if (region[f] == id) (truth.count(static_cast<int>(f)) ? ++intersection : ++uni);
    const double iou = static_cast<double>(intersection) / static_cast<double>(uni);
    // The smallest bump has 19 faces at this resolution: its region may take the one band of
    // faces straddling the rim (allowed below), so the test is coverage, not IoU.
    EXPECT_GE(static_cast<double>(intersection), 0.9 * static_cast<double>(truth.size()))
        << "bump " << b << " (" << truth.size() << " faces): region " << id << " IoU " << iou;
    EXPECT_TRUE(matched_ids.insert(id).second) << "bump " << b << " shares region " << id << " with another bump";
    const std::set<int> near = with_vertex_neighbours(mesh_, bumps_[b]);
    allowed.insert(near.begin(), near.end());
  }
  for (std::size_t f = 0; f < region.size(); ++f)
    if (region[f] >= 0) {
      EXPECT_TRUE(allowed.count(static_cast<int>(f))) << "face " << f << " selected away from every bump";
    }

  // Ids ordered by decreasing area; the summaries agree with the ids.
  for (std::size_t r = 0; r + 1 < report.regions.size(); ++r)
    EXPECT_GE(report.regions[r].area, report.regions[r + 1].area);
  for (std::size_t r = 0; r < report.regions.size(); ++r)
    EXPECT_EQ(report.regions[r].faces,
              static_cast<std::size_t>(std::count(region.begin(), region.end(), static_cast<int>(r))));
  // The base sphere has radius 0.5: H_ref is its curvature 2 (more than half of the area),
  // smoothed at the largest diffusion length, which lowers it near the bump rims; the median
  // stays within 10 % and below the base sphere's own H (2 to 2 %): the smoothing acted.
  EXPECT_GT(report.reference_mean_curvature, 1.8);
  EXPECT_LT(report.reference_mean_curvature, 1.96);
}

TEST_F(BumpySphere, ResultDoesNotDependOnScale) {
  const std::vector<int> unit = select_spherical_regions(mesh_, x_, RegionOptions{});
  for (double s : {1e-3, 1e3}) {
    const Positions scaled = s * x_;
    EXPECT_EQ(select_spherical_regions(mesh_, scaled, RegionOptions{}), unit) << "scale " << s;
  }
}

TEST_F(BumpySphere, StoreRegionsWritesTheFaceMap) {
  const std::vector<int> region = select_spherical_regions(mesh_, x_, RegionOptions{});
  store_regions(mesh_, region);
  store_regions(mesh_, region);  // overwriting is allowed
  const auto map = property::get_map<FaceIndex, int>(mesh_, property::REGION);
  for (FaceIndex f : mesh_.faces()) EXPECT_EQ(map[f], region[f.idx()]);
}

// Before: a NaN position gave no region (every curvature NaN), as if the mesh were smooth.
TEST_F(BumpySphere, PositionsThatAreNotFiniteAreAUsageErrorNamingTheVertex) {
  for (const RegionMethod method : {RegionMethod::Caps, RegionMethod::Tips, RegionMethod::Parts}) {
    Positions x = x_;
    x(7, 0) = std::nan("");
    RegionOptions o;
    o.method = method;
    try {
      select_spherical_regions(mesh_, x, o);
      ADD_FAILURE() << "a NaN position was accepted";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find("vertex 7"), std::string::npos) << e.what();
    }
  }
}

// Before: an id of -7 was stored (and written) as if it were -1, and a mesh with removed faces was
// refused as "319 ids for 319 faces".
TEST_F(BumpySphere, StoreRegionsRefusesIdsBelowMinusOneAndGarbageSayingWhich) {
  std::vector<int> region(mesh_.number_of_faces(), -1);
  region[5] = -7;
  try {
    store_regions(mesh_, region);
    ADD_FAILURE() << "an id of -7 was stored";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("face 5 has region id -7"), std::string::npos) << e.what();
  }
  EXPECT_THROW(write_region_file(temp_path("minus_seven.txt"), region), UsageError);
  EXPECT_FALSE(std::filesystem::exists(temp_path("minus_seven.txt")));
  Mesh removed = mesh_;
  removed.remove_face(*removed.faces().begin());
  try {
    store_regions(removed, std::vector<int>(removed.number_of_faces(), -1));
    ADD_FAILURE() << "a mesh with garbage was accepted";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("removed elements"), std::string::npos) << e.what();
  }
}

TEST_F(BumpySphere, MarkWritesTheSelectionAndTheCurvatureIntoTheMaps) {
  RegionReport expected_report, report;
  const std::vector<int> expected = select_spherical_regions(mesh_, x_, RegionOptions{}, &expected_report);
  EXPECT_EQ(stored_regions(mesh_), std::vector<int>(mesh_.number_of_faces(), -1)) << "no map yet: no region";
  const std::size_t n = mark_spherical_regions(mesh_, x_, RegionOptions{}, &report);
  EXPECT_EQ(n, 3u);
  EXPECT_EQ(report.regions.size(), expected_report.regions.size());
  const auto map = property::get_map<FaceIndex, int>(mesh_, property::REGION);
  for (FaceIndex f : mesh_.faces()) ASSERT_EQ(map[f], expected[f.idx()]) << "face " << f.idx();
  EXPECT_EQ(stored_regions(mesh_), expected);
  const CurvatureField c = compute_curvature(mesh_, x_);
  const auto H = property::get_map<VertexIndex, double>(mesh_, property::MEAN_CURVATURE);
  const auto K = property::get_map<VertexIndex, double>(mesh_, property::GAUSSIAN_CURVATURE);
  for (VertexIndex v : mesh_.vertices()) {
    ASSERT_EQ(H[v], c.mean(static_cast<Eigen::Index>(v.idx()))) << "vertex " << v.idx();
    ASSERT_EQ(K[v], c.gaussian(static_cast<Eigen::Index>(v.idx()))) << "vertex " << v.idx();
  }
  // A second run overwrites the maps (here with no region at all).
  RegionOptions none;
  none.min_curvature_contrast = 100.0;
  EXPECT_EQ(mark_spherical_regions(mesh_, x_, none), 0u);
  EXPECT_EQ(stored_regions(mesh_), std::vector<int>(mesh_.number_of_faces(), -1));
}

TEST_F(BumpySphere, ColouredPlyHasTheMapsOfTheMesh) {
  mark_spherical_regions(mesh_, x_, RegionOptions{});
  const std::vector<int> region = stored_regions(mesh_);
  const std::string path = temp_path("bumps.ply");
  write_region_ply(path, mesh_, x_);
  const Mesh back = read_input_mesh(path);
  ASSERT_EQ(back.number_of_faces(), mesh_.number_of_faces());
  const Positions xb = positions_from_mesh(back);
  EXPECT_EQ(xb, x_);  // 17 digits: lossless
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("property int region"), std::string::npos);
  EXPECT_NE(text.find("property double mean_curvature"), std::string::npos);
  EXPECT_NE(text.find("property double gaussian_curvature"), std::string::npos);
  // Face rows: "3 a b c <region> <r g b a>" in the order the maps were attached (colour first).
  const std::size_t body = text.find("end_header\n") + 11;
  std::istringstream rows(text.substr(body));
  std::string line;
  for (std::size_t i = 0; i < mesh_.number_of_vertices(); ++i) std::getline(rows, line);
  for (FaceIndex f : mesh_.faces()) {
    ASSERT_TRUE(std::getline(rows, line));
    std::istringstream t(line);
    int n = 0, a = 0, b = 0, c = 0, red = 0, green = 0, blue = 0, alpha = 0, id = 0;
    t >> n >> a >> b >> c >> red >> green >> blue >> alpha >> id;
    ASSERT_EQ(id, region[f.idx()]) << line;
    const auto rgb = region_colour(region[f.idx()]);
    ASSERT_EQ(red, rgb[0]) << line;
    ASSERT_EQ(blue, rgb[2]) << line;
  }
  // Without the curvature maps the file has no curvature columns.
  Mesh plain = read_input_mesh(mesh_path("bumpy_sphere.off"));
  store_regions(plain, region);
  write_region_ply(path, plain, x_);
  std::ifstream in2(path);
  text.assign((std::istreambuf_iterator<char>(in2)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text.find("mean_curvature"), std::string::npos);
  EXPECT_NE(text.find("property int region"), std::string::npos);
}

TEST(RegionSelection, PlainSphereHasNoRegion) {
  // Decision: a local spherical structure must be clearly more curved than the rest of the
  // surface. On a plain sphere every cap has the curvature of the whole (H_ref), so nothing is
  // selected (the anisotropic energy would then act on the whole shell, which is not "local").
  for (int level : {2, 3, 4}) {
    const test::TriMesh m = test::icosphere(level, 0.5);
    const Mesh mesh = test::to_surface_mesh(m);
    RegionReport report;
    const std::vector<int> region = select_spherical_regions(mesh, m.x, RegionOptions{}, &report);
    EXPECT_EQ(std::count(region.begin(), region.end(), -1), static_cast<long>(region.size())) << "level " << level;
    EXPECT_NEAR(report.reference_mean_curvature, 2.0, 0.02);
  }
  const Mesh uv = read_input_mesh(mesh_path("uv_sphere.off"));
  const std::vector<int> region = select_spherical_regions(uv, positions_from_mesh(uv), RegionOptions{});
  EXPECT_EQ(std::count(region.begin(), region.end(), -1), static_cast<long>(region.size()));
}

TEST(RegionSelection, FlatSidedMeshesHaveNoRegion) {
  // A cube and a torus have no spherical structure: corners are single vertices (no sphere to
  // fit), a torus has no umbilic convex patch more curved than its median.
  for (const char* name : {"cube.off", "torus.off", "octahedron.off"}) {
    const Mesh mesh = read_input_mesh(mesh_path(name));
    const std::vector<int> region = select_spherical_regions(mesh, positions_from_mesh(mesh), RegionOptions{});
    EXPECT_EQ(std::count(region.begin(), region.end(), -1), static_cast<long>(region.size())) << name;
  }
}

TEST(RegionSelection, BadOptionsAreUsageErrors) {
  const test::TriMesh m = test::icosphere(1, 1.0);
  const Mesh mesh = test::to_surface_mesh(m);
  RegionOptions o;
  o.fit_tolerance = -0.1;
  EXPECT_THROW(select_spherical_regions(mesh, m.x, o), UsageError);
  o = RegionOptions{};
  o.max_compactness = 0.0;
  EXPECT_THROW(select_spherical_regions(mesh, m.x, o), UsageError);
  o.max_compactness = std::nan("");
  EXPECT_THROW(select_spherical_regions(mesh, m.x, o), UsageError);
  // A cap on a sphere is below 1 (a hemisphere is 0.5): a bound below 1 is a real threshold.
  o.max_compactness = 0.5;
  EXPECT_NO_THROW(check_region_options(o));
  o = RegionOptions{};
  o.min_area_fraction = 0.5;
  o.max_area_fraction = 0.1;
  EXPECT_THROW(select_spherical_regions(mesh, m.x, o), UsageError);
}

TEST(RegionFile, RoundTrip) {
  const std::vector<int> ids{-1, 1, 0, 0, -1, 2, 1, -1, 2, 0};
  const std::string path = temp_path("round_trip.txt");
  write_region_file(path, ids);
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "2 3 9\n1 6\n5 8\n");  // the documented format, faces ascending
  const std::vector<std::vector<int>> regions = read_region_file(path, ids.size());
  EXPECT_EQ(face_ids_from_regions(regions, ids.size()), ids);
  EXPECT_EQ(regions_from_face_ids(ids), regions);
}

TEST(RegionFile, CommentsBlankLinesTabsAndCrlfAreAccepted) {
  const std::string path = temp_path("comments.txt");
  write_file(path, "# bumps\n\n4\t2 7\r\n   \n3\n");
  const std::vector<std::vector<int>> regions = read_region_file(path, 8);
  ASSERT_EQ(regions.size(), 2u);
  EXPECT_EQ(regions[0], (std::vector<int>{4, 2, 7}));
  EXPECT_EQ(regions[1], (std::vector<int>{3}));
}

/// Expects read_region_file to throw InputError whose message contains `where` and `what`.
void expect_bad_file(const std::string& name, const std::string& text, std::size_t num_faces,
                     const std::string& where, const std::string& what) {
  const std::string path = temp_path(name);
  write_file(path, text);
  try {
    read_region_file(path, num_faces);
    ADD_FAILURE() << name << ": no error for\n" << text;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path + ":" + where + ":"), std::string::npos) << name << ": " << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << name << ": " << msg;
  }
}

TEST(RegionFile, BadFilesNameTheLine) {
  expect_bad_file("not_integer.txt", "1 2 3\n4 five 6\n", 10, "2", "'five' is not a face index");
  expect_bad_file("fraction.txt", "1 2.5\n", 10, "1", "'2.5' is not a face index");
  expect_bad_file("negative.txt", "1\n\n-1\n", 10, "3", "'-1' is not a face index");
  expect_bad_file("out_of_range.txt", "0 1\n2 3\n9 10\n", 10, "3", "face 10 is out of range");
  expect_bad_file("huge.txt", "99999999999999999999999\n", 10, "1", "out of range");
  expect_bad_file("duplicate.txt", "0 1\n2 1\n", 10, "2", "face 1 is already listed on line 1");
}

// Review 7 (F9): a lone "\r" ends a line, as in the OBJ and PLY readers. The reader split at
// "\n" only and took the "\r" for a blank: the two regions of a file saved with classic Mac line
// ends were read as one region, without a word.
TEST(RegionFile, ALoneCarriageReturnEndsALine) {
  const std::string path = temp_path("cr.txt");
  write_file(path, "1 2 3\r4 5 6\r");
  const std::vector<std::vector<int>> regions = read_region_file(path, 8);
  ASSERT_EQ(regions.size(), 2u);
  EXPECT_EQ(regions[0], (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(regions[1], (std::vector<int>{4, 5, 6}));
  // Line ends mixed in one file: each "\r\n" is one line end, each lone "\r" or "\n" one.
  write_file(path, "0.5: 1\r\r\n# 2\r2\n\r7");
  const RegionFile mixed = read_region_file_with_strengths(path, 8);
  ASSERT_EQ(mixed.regions.size(), 3u);
  EXPECT_EQ(mixed.regions[0], (std::vector<int>{1}));
  EXPECT_EQ(mixed.regions[1], (std::vector<int>{2}));
  EXPECT_EQ(mixed.regions[2], (std::vector<int>{7}));
  EXPECT_EQ(mixed.strength, (std::vector<double>{0.5, 1.0, 1.0}));
  // A message names the line as an editor showing those line ends numbers it.
  expect_bad_file("cr_bad.txt", "1\r2\rx\r", 8, "3", "'x' is not a face index");
}

// Review 7: zero-padded ids (as a spreadsheet pads them) are their value; past 18 characters one
// was "out of range". A UTF-8 byte order mark (Windows editors write one) is skipped; it was read
// as part of the first id, refused as "'1' is not a face index" with the mark printed invisibly.
TEST(RegionFile, ZeroPaddedIdsAndAByteOrderMarkAreRead) {
  const std::string path = temp_path("padded.txt");
  write_file(path, "000000000000000000000000000001 0007\n00000000000000000000000000\n");
  const std::vector<std::vector<int>> padded = read_region_file(path, 8);
  ASSERT_EQ(padded.size(), 2u);
  EXPECT_EQ(padded[0], (std::vector<int>{1, 7}));
  EXPECT_EQ(padded[1], (std::vector<int>{0}));
  write_file(path,
             "\xEF\xBB\xBF"
             "1 2\r\n3\r\n");
  const std::vector<std::vector<int>> marked = read_region_file(path, 8);
  ASSERT_EQ(marked.size(), 2u);
  EXPECT_EQ(marked[0], (std::vector<int>{1, 2}));
  EXPECT_EQ(marked[1], (std::vector<int>{3}));
  expect_bad_file("padded_high.txt", "0000000000000000000000000000010\n", 10, "1",
                  "face 0000000000000000000000000000010 is out of range (the mesh has 10 faces)");
  expect_bad_file("padded_twice.txt", "1\n001\n", 10, "2", "face 001 is already listed on line 1");
}

TEST(RegionFile, ALineMayStartWithItsStrength) {
  // Issue 55, item 3: "S:" before the faces is the region's strength; without it, 1. A file
  // without strengths reads as before (the other RegionFile tests).
  const std::string path = temp_path("strengths.txt");
  write_file(path, "# strengths\n0.25: 4 2\n7\n  1: 3\t5\n0: 6\n");
  const RegionFile file = read_region_file_with_strengths(path, 8);
  ASSERT_EQ(file.regions.size(), 4u);
  EXPECT_EQ(file.regions[0], (std::vector<int>{4, 2}));
  EXPECT_EQ(file.regions[1], (std::vector<int>{7}));
  EXPECT_EQ(file.regions[2], (std::vector<int>{3, 5}));
  EXPECT_EQ(file.regions[3], (std::vector<int>{6}));
  EXPECT_EQ(file.strength, (std::vector<double>{0.25, 1.0, 1.0, 0.0}));
  EXPECT_EQ(read_region_file(path, 8), file.regions);
  // The ':' need not stand apart (the docs name no blank): "0.5:12 13" had been refused as
  // "'0.5:12' is not a face index", " 0.5 : 3" as "'0.5' is not a face index".
  write_file(path, "0.5:4 2\n 0.75 : 3\n\t1:5\n");
  const RegionFile joined = read_region_file_with_strengths(path, 8);
  ASSERT_EQ(joined.regions.size(), 3u);
  EXPECT_EQ(joined.regions[0], (std::vector<int>{4, 2}));
  EXPECT_EQ(joined.regions[1], (std::vector<int>{3}));
  EXPECT_EQ(joined.regions[2], (std::vector<int>{5}));
  EXPECT_EQ(joined.strength, (std::vector<double>{0.5, 0.75, 1.0}));
}

TEST(RegionFile, BadStrengthsNameTheLine) {
  expect_bad_file("strength_high.txt", "1 2\n1.5: 3\n", 10, "2", "strength '1.5' is not a number in [0, 1]");
  expect_bad_file("strength_negative.txt", "-0.1: 3\n", 10, "1", "strength '-0.1' is not a number in [0, 1]");
  expect_bad_file("strength_word.txt", "half: 3\n", 10, "1", "strength 'half' is not a number in [0, 1]");
  expect_bad_file("strength_nan.txt", "nan: 3\n", 10, "1", "strength 'nan' is not a number in [0, 1]");
  expect_bad_file("strength_trailing.txt", "0.5x: 3\n", 10, "1", "strength '0.5x' is not a number in [0, 1]");
  expect_bad_file("strength_alone.txt", "0 1\n0.5:\n", 10, "2", "a strength with no face after it");
  expect_bad_file("strength_second.txt", "3 0.5: 4\n", 10, "1",
                  "strength '3 0.5' is not a number in [0, 1]");
  expect_bad_file("strength_empty.txt", "0 1\n  : 3\n", 10, "2",
                  "a ':' with no strength before it");
  expect_bad_file("strength_twice.txt", "0.5: 0.5: 3\n", 10, "1", "'0.5:' is not a face index");
}

TEST(RegionFile, MissingFileIsAnInputError) {
  EXPECT_THROW(read_region_file(temp_path("does_not_exist.txt"), 10), InputError);
}

TEST(RegionFile, IdsWithAGapCannotBeWritten) {
  EXPECT_THROW(write_region_file(temp_path("gap.txt"), {0, 2, -1}), UsageError);
  EXPECT_THROW(face_ids_from_regions({{0, 1}, {1}}, 3), UsageError);
  EXPECT_THROW(face_ids_from_regions({{3}}, 3), UsageError);
}

TEST(RegionSelection, PaperMeshesReport) {
  // No ground truth for these: print what is found (count, faces, area fraction) and check
  // only the contract (ids 0..n-1, sizes within the area bounds, summaries consistent).
  int found = 0;
  for (const char* name : {"hand", "bear"}) {
    const std::string path = std::string(test::PAPER_MESH_DIR) + "/" + name + ".off";
    if (!fs::exists(path)) continue;
    ++found;
    const Mesh mesh = read_input_mesh(path);
    RegionReport report;
    const RegionOptions options;
    const std::vector<int> region = select_spherical_regions(mesh, positions_from_mesh(mesh), options, &report);
    std::cout << name << ": " << report.regions.size() << " regions (H_ref " << report.reference_mean_curvature
              << ", " << report.seed_vertices << " seeds, " << report.dropped_small << " small caps dropped)\n";
    for (std::size_t r = 0; r < report.regions.size(); ++r) {
      const RegionSummary& s = report.regions[r];
      std::cout << "  region " << r << ": " << s.faces << " faces, area fraction " << s.area_fraction << ", contrast "
                << s.contrast << '\n';
      EXPECT_GE(s.area_fraction, options.min_area_fraction) << name << " region " << r;
      EXPECT_LE(s.area_fraction, options.max_area_fraction) << name << " region " << r;
      EXPECT_EQ(s.faces, static_cast<std::size_t>(std::count(region.begin(), region.end(), static_cast<int>(r))));
    }
    for (int id : region) EXPECT_LT(id, static_cast<int>(report.regions.size()));
  }
  if (found == 0) GTEST_SKIP() << "no paper meshes in " << test::PAPER_MESH_DIR << "; run scripts/fetch_paper_meshes.sh";
}

}  // namespace
}  // namespace shellcontract
