// The tip finder (RegionMethod::Tips, docs/math/tip-finder.md): the ends of a capsule with the
// area its stop rule implies, the two ends of a dumbbell inside their bulbs, no region on a
// sphere, compact regions (compactness measured here from the face list), identical face sets
// under rotation, scaling and vertex order, and the same regions on bear split in four.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "shellcontract/mesh_io.hpp"
#include "shellcontract/regions.hpp"
#include "support/cgal_mesh.hpp"
#include "support/cli_runner.hpp"
#include "support/mesh_fixtures.hpp"
#include "support/region_fixtures.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
constexpr double PI = 3.14159265358979323846;
/// The documented stop rule (docs/math/tip-finder.md): a disc stops when the length of its
/// area-weighted mean unit normal falls to 0.4.
constexpr double WRAPPED = 0.4;

std::vector<int> tips(const test::TriMesh& m, RegionReport* report = nullptr) {
  RegionOptions o;
  o.method = RegionMethod::Tips;
  return select_spherical_regions(test::to_surface_mesh(m), m.x, o, report);
}

double area_of(const test::TriMesh& m, const std::vector<int>& faces) {
  double a = 0.0;
  for (int f : faces) {
    const Vec3 p0(m.x.row(m.faces(f, 0))), p1(m.x.row(m.faces(f, 1))), p2(m.x.row(m.faces(f, 2)));
    a += 0.5 * (p1 - p0).cross(p2 - p0).norm();
  }
  return a;
}

/// The faces around a vertex (the pole fans of a surface of revolution).
std::set<int> faces_at(const test::TriMesh& m, int v) {
  std::set<int> out;
  for (Eigen::Index j = 0; j < m.faces.rows(); ++j)
    for (int k = 0; k < 3; ++k)
      if (m.faces(j, k) == v) out.insert(static_cast<int>(j));
  return out;
}

bool holds(const std::vector<int>& region, const std::set<int>& faces) {
  const std::set<int> r(region.begin(), region.end());
  for (int f : faces)
    if (!r.count(f)) return false;
  return true;
}

void expect_compact(const test::TriMesh& m, const std::vector<int>& ids) {
  for (const std::vector<int>& r : regions_from_face_ids(ids))
    EXPECT_LE(test::compactness_by_edge_count(m, r), 2.0);
}

TEST(TipFinder, DefaultIsTheCapFinder) {
  EXPECT_EQ(RegionOptions{}.method, RegionMethod::Caps);  // opt-in: the default must not change
}

TEST(TipFinder, CapsuleGivesItsTwoEndsWithTheAreaOfTheStopRule) {
  // A capsule of radius r, cylinder length L = 4r. A disc from a pole covers the hemisphere
  // (mean normal: pi r^2 axis over 2 pi r^2, length 1/2) and then a band of the cylinder of
  // height h, whose normals cancel round the axis: length r / (2 (r + h)) = WRAPPED gives
  // h = r (1 / (2 WRAPPED) - 1) = r / 4. Each end's share: (2 pi r^2 + 2 pi r h) / (4 pi r^2 +
  // 2 pi r L) = 2.5 / 12 = 0.208 (the bare hemisphere would be 2 / 12 = 0.167). The two discs do
  // not meet, so nearest-centre ownership leaves them whole.
  const double r = 1.0, L = 4.0;
  const test::TriMesh m = test::revolution(test::capsule_profile(r, L), 120, 64);
  const double h = r * (1.0 / (2.0 * WRAPPED) - 1.0);
  const double expected =
      (2.0 * PI * r * r + 2.0 * PI * r * h) / (4.0 * PI * r * r + 2.0 * PI * r * L);
  const std::vector<int> ids = tips(m);
  const std::vector<std::vector<int>> regions = regions_from_face_ids(ids);
  ASSERT_EQ(regions.size(), 2u);
  const double total = area_of(m, std::vector<int>([&] {
                                 std::vector<int> all(static_cast<std::size_t>(m.faces.rows()));
                                 for (std::size_t j = 0; j < all.size(); ++j)
                                   all[j] = static_cast<int>(j);
                                 return all;
                               }()));
  const std::set<int> top = faces_at(m, 0), bottom = faces_at(m, static_cast<int>(m.x.rows()) - 1);
  EXPECT_TRUE((holds(regions[0], top) && holds(regions[1], bottom)) ||
              (holds(regions[1], top) && holds(regions[0], bottom)));
  for (const std::vector<int>& reg : regions) EXPECT_NEAR(area_of(m, reg) / total, expected, 0.006);
  expect_compact(m, ids);
}

TEST(TipFinder, DumbbellGivesItsTwoEndsInsideTheirBulbs) {
  // Two unit spheres at z = +-3 joined by a neck of radius 0.4: the ends are the two poles.
  // A disc from a pole is a spherical cap until it wraps: (1 + cos theta) / 2 = WRAPPED at
  // cos theta = 2 WRAPPED - 1 = -0.2, area 2 pi (1 - cos theta), before it reaches the crease
  // where the bulb meets the neck (theta = pi - asin 0.4). So each region stays on its own bulb
  // and has the area of that cap. (With the spheres closer, c = 1.6, the cap would exceed
  // max_area_fraction and there would be no region, as on a plain sphere.)
  const double c = 3.0, n = 0.4;
  const test::TriMesh m = test::revolution(test::dumbbell_profile(c, n), 160, 64);
  const std::vector<int> ids = tips(m);
  const std::vector<std::vector<int>> regions = regions_from_face_ids(ids);
  ASSERT_EQ(regions.size(), 2u);
  const std::set<int> top = faces_at(m, 0), bottom = faces_at(m, static_cast<int>(m.x.rows()) - 1);
  const double crease = c + std::cos(PI - std::asin(n));  // |z| of the crease
  const double cap_area = 2.0 * PI * (1.0 - (2.0 * WRAPPED - 1.0));
  for (const std::vector<int>& reg : regions) {
    const bool is_top = holds(reg, top);
    EXPECT_TRUE(is_top != holds(reg, bottom)) << "each region holds exactly one pole";
    for (int f : reg) {
      const double z =
          (m.x(m.faces(f, 0), 2) + m.x(m.faces(f, 1), 2) + m.x(m.faces(f, 2), 2)) / 3.0;
      EXPECT_GT(is_top ? z : -z, crease) << "face " << f;
    }
    EXPECT_NEAR(area_of(m, reg), cap_area, 0.03 * cap_area);
  }
  // Mirror images: the same area up to the triangulation.
  EXPECT_NEAR(area_of(m, regions[0]), area_of(m, regions[1]), 0.05 * area_of(m, regions[0]));
  expect_compact(m, ids);
}

TEST(TipFinder, DumbbellVertexOrderDoesNotMatter) {
  // Ties abound on a surface of revolution; they are broken by positions, never by indices.
  const test::TriMesh m = test::revolution(test::dumbbell_profile(3.0, 0.4), 80, 32);
  const std::vector<int> ids = tips(m);
  ASSERT_EQ(regions_from_face_ids(ids).size(), 2u);
  EXPECT_EQ(test::face_sets(tips(test::shuffle_vertices(m, 7))), test::face_sets(ids));
}

TEST(TipFinder, PlainSphereHasNoRegion) {
  // A sphere has no end: a cap of half-angle theta has mean normal length (1 + cos theta) / 2,
  // which reaches WRAPPED only at cos theta = 2 WRAPPED - 1 = -0.2, a cap of (1 - cos theta) / 2
  // = 60 % of the area, beyond max_area_fraction (25 %). Every tip's disc is dropped as too
  // wide, so there is no region (as the cap finder: a plain sphere is no part of itself).
  RegionReport report;
  const std::vector<int> ids = tips(test::icosphere(4), &report);
  EXPECT_TRUE(regions_from_face_ids(ids).empty());
  EXPECT_GE(report.seed_vertices, 1u);
  EXPECT_EQ(report.dropped_large, report.seed_vertices);
}

class BearTips : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(test::paper_mesh("bear")))
      GTEST_SKIP() << "bear.off is absent; run scripts/fetch_paper_meshes.sh";
    m_ = test::to_tri_mesh(read_input_mesh(test::paper_mesh("bear")));
    ids_ = tips(m_);
    ASSERT_GE(regions_from_face_ids(ids_).size(), 4u) << "ears, arms, feet: bear has ends to find";
  }
  test::TriMesh m_;
  std::vector<int> ids_;
};

TEST_F(BearTips, RegionsAreCompact) { expect_compact(m_, ids_); }

TEST_F(BearTips, RotationAndScalingGiveTheSameFaceSets) {
  EXPECT_EQ(test::face_sets(tips(test::moved(m_))), test::face_sets(ids_));
}

TEST_F(BearTips, VertexOrderDoesNotMatter) {
  EXPECT_EQ(test::face_sets(tips(test::shuffle_vertices(m_, 12345))), test::face_sets(ids_));
}

TEST_F(BearTips, SplittingEveryFaceInFourFindsTheSameRegions) {
  // Region by region, both ways: every region has a partner with IoU >= 0.8.
  const std::vector<int> fine_ids = tips(test::split_in_four(m_));
  std::string where;
  EXPECT_GE(test::worst_subdivision_iou(ids_, fine_ids, &where), 0.8) << where;
}

TEST(TipFinder, CliMethodChoosesTheFinderAndRefusesUnknownValues) {
  // `regions --method tips` writes the library's tip regions; an unknown method and --region-at
  // with tips are usage errors (exit 1) that name the problem.
  const fs::path dir = fs::temp_directory_path() / ("sc_tip_cli_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const test::TriMesh m = test::revolution(test::dumbbell_profile(3.0, 0.4), 80, 32);
  const Mesh mesh = test::to_surface_mesh(m);
  const std::string in = (dir / "dumbbell.off").string(), out = (dir / "r.ply").string(),
                    list = (dir / "r.txt").string();
  write_mesh_atomic(in, mesh, m.x);
  auto r = test::run_cli({"regions", in, "-o", out, "--method", "blobs"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("expected caps, tips or parts"), std::string::npos) << r.output;
  r = test::run_cli({"regions", in, "-o", out, "--method", "tips", "--region-at", "0,0,4"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  r = test::run_cli({"regions", in, "-o", out, "--method", "tips", "--face-list", list});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<std::vector<int>> got = read_region_file(list, mesh.number_of_faces());
  const Mesh back = read_input_mesh(in);  // the file's positions, as the CLI read them
  RegionOptions o;
  o.method = RegionMethod::Tips;
  const std::vector<int> ids = select_spherical_regions(back, positions_from_mesh(back), o);
  EXPECT_EQ(std::set<std::vector<int>>(got.begin(), got.end()), test::face_sets(ids));
  EXPECT_EQ(got.size(), 2u);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace shellcontract
