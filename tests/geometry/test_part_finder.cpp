// The part finder (RegionMethod::Parts, docs/math/part-finder.md): the tip finder's ends and the
// cap finder's heads and bumps. A capsule, where the cap finder keeps nothing, gives exactly the
// tip finder's two ends; bumpy_sphere gives its three bumps, which the tip finder
// misses; on bear the head is the ball of the cap finder's head, the ends the tip finder's; compact
// regions, identical face sets under rotation, scaling and vertex order, the same regions on
// bear split in four; the CLI's --method parts.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
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

std::vector<int> find(const test::TriMesh& m, RegionMethod method) {
  RegionOptions o;
  o.method = method;
  return select_spherical_regions(test::to_surface_mesh(m), m.x, o);
}

double area_of(const test::TriMesh& m, const std::set<int>& faces) {
  double a = 0.0;
  for (int f : faces) {
    const Vec3 p0(m.x.row(m.faces(f, 0))), p1(m.x.row(m.faces(f, 1))), p2(m.x.row(m.faces(f, 2)));
    a += 0.5 * (p1 - p0).cross(p2 - p0).norm();
  }
  return a;
}

/// The largest IoU (by area) of `part` with a region of `ids`.
double best_iou(const test::TriMesh& m, const std::set<int>& part, const std::vector<int>& ids) {
  double best = 0.0;
  for (const std::vector<int>& r : regions_from_face_ids(ids)) {
    std::set<int> both, either(part);
    for (int f : r) {
      if (part.count(f)) both.insert(f);
      either.insert(f);
    }
    best = std::max(best, area_of(m, both) / area_of(m, either));
  }
  return best;
}

TEST(PartFinder, DefaultIsTheCapFinder) {
  EXPECT_EQ(RegionOptions{}.method, RegionMethod::Caps);  // opt-in: the default must not change
}

TEST(PartFinder, CapsuleGivesTheTipFindersTwoEndsUnchanged) {
  // The cap finder keeps no region on this capsule (checked first), so nothing covers or cuts
  // the tip finder's two ends: the part finder must hand them on face for face.
  const test::TriMesh m = test::revolution(test::capsule_profile(1.0, 4.0), 120, 64);
  const std::vector<int> tips = find(m, RegionMethod::Tips);
  ASSERT_EQ(regions_from_face_ids(tips).size(), 2u);
  ASSERT_TRUE(regions_from_face_ids(find(m, RegionMethod::Caps)).empty());
  EXPECT_EQ(test::face_sets(find(m, RegionMethod::Parts)), test::face_sets(tips));
}

TEST(PartFinder, BumpySphereGivesItsThreeBumps) {
  // Three bumps on a sphere: the tip finder finds none of them (a bump barely changes the
  // protrusion field), the cap finder does and no tip region covers them, so each bump of
  // meshes/bumpy_sphere.bumps.txt has a region that overlaps it with IoU >= 0.5.
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/bumpy_sphere.off");
  const test::TriMesh m = test::to_tri_mesh(mesh);
  const std::vector<std::vector<int>> bumps =
      read_region_file(std::string(test::MESH_DIR) + "/bumpy_sphere.bumps.txt", mesh.number_of_faces());
  ASSERT_EQ(bumps.size(), 3u);
  const std::vector<int> ids = find(m, RegionMethod::Parts);
  for (const std::vector<int>& b : bumps)
    EXPECT_GE(best_iou(m, std::set<int>(b.begin(), b.end()), ids), 0.5) << "bump at face " << b.front();
}

class BearParts : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(test::paper_mesh("bear")))
      GTEST_SKIP() << "bear.off is absent; run scripts/fetch_paper_meshes.sh";
    m_ = test::to_tri_mesh(read_input_mesh(test::paper_mesh("bear")));
    ids_ = find(m_, RegionMethod::Parts);
    ASSERT_GE(regions_from_face_ids(ids_).size(), 5u) << "head, ears, arms, feet";
  }
  test::TriMesh m_;
  std::vector<int> ids_;
};

Vec3 centroid(const test::TriMesh& m, int f) {
  return (Vec3(m.x.row(m.faces(f, 0))) + Vec3(m.x.row(m.faces(f, 1))) + Vec3(m.x.row(m.faces(f, 2)))) / 3.0;
}

TEST_F(BearParts, HeadIsTheBallOfTheCapFindersHeadAndTheEndsAreTheTipFinders) {
  // The cap finder's largest region on bear is its head (lab/regions/iou_table.md), a hemisphere
  // of its sphere, which tip regions cover less than half of. Here it is the ball: a region that
  // holds the cap's faces outside the tip regions, adds only faces within (1 + residual) radii of
  // the sphere's centre, and reaches past the hemisphere (faces behind the centre, seen along the
  // cap's axis). Every tip region not mostly inside the head cap (ears, arms, feet) is a region
  // here as it is.
  RegionReport cap_report;
  RegionOptions o;
  const std::vector<int> cap_ids = select_spherical_regions(test::to_surface_mesh(m_), m_.x, o, &cap_report);
  const std::vector<std::vector<int>> caps = regions_from_face_ids(cap_ids);
  const std::vector<int> tip_ids = find(m_, RegionMethod::Tips);
  std::set<int> tip_faces;
  for (std::size_t f = 0; f < tip_ids.size(); ++f)
    if (tip_ids[f] >= 0) tip_faces.insert(static_cast<int>(f));
  const std::set<int> head(caps.front().begin(), caps.front().end());
  const RegionSummary& sphere = cap_report.regions.front();
  Vec3 axis = Vec3::Zero();
  for (int f : head) axis += area_of(m_, {f}) * (centroid(m_, f) - sphere.centre).normalized();
  axis.normalize();
  const auto free_face = std::find_if(head.begin(), head.end(), [&](int f) { return !tip_faces.count(f); });
  ASSERT_NE(free_face, head.end());
  const std::vector<std::vector<int>> got = regions_from_face_ids(ids_);
  ASSERT_GE(ids_[static_cast<std::size_t>(*free_face)], 0) << "the head's free faces are in a region";
  const std::vector<int>& ball = got[static_cast<std::size_t>(ids_[static_cast<std::size_t>(*free_face)])];
  const std::set<int> in_ball(ball.begin(), ball.end());
  for (int f : head) {
    if (!tip_faces.count(f)) {
      EXPECT_TRUE(in_ball.count(f)) << "cap face " << f;
    }
  }
  std::set<int> behind;
  for (int f : in_ball) {
    if (head.count(f)) continue;
    EXPECT_LE((centroid(m_, f) - sphere.centre).norm(), (1.0 + sphere.residual) * sphere.radius) << "face " << f;
    if ((centroid(m_, f) - sphere.centre).dot(axis) < 0.0) behind.insert(f);
  }
  EXPECT_GT(area_of(m_, behind), 0.0) << "the ball reaches past the cap's hemisphere";
  const std::set<std::vector<int>> sets(got.begin(), got.end());
  int ends = 0, pieces = 0;
  for (const std::vector<int>& t : regions_from_face_ids(tip_ids)) {
    std::set<int> in_head;
    for (int f : t)
      if (head.count(f)) in_head.insert(f);
    if (area_of(m_, in_head) <= 0.5 * area_of(m_, std::set<int>(t.begin(), t.end()))) {
      EXPECT_TRUE(sets.count(t)) << "tip region at face " << t.front();
      ++ends;
    } else {
      EXPECT_FALSE(sets.count(t)) << "the crown's tip region is a piece of the head: " << t.front();
      ++pieces;
    }
  }
  EXPECT_GE(ends, 6) << "two ears, two arms, two feet";
  EXPECT_GE(pieces, 1) << "the tip region on the crown, between the ears";
}

TEST_F(BearParts, RegionsAreCompact) {
  for (const std::vector<int>& r : regions_from_face_ids(ids_)) EXPECT_LE(test::compactness_by_edge_count(m_, r), 2.0);
}

TEST_F(BearParts, RotationAndScalingGiveTheSameFaceSets) {
  EXPECT_EQ(test::face_sets(find(test::moved(m_), RegionMethod::Parts)), test::face_sets(ids_));
}

TEST_F(BearParts, VertexOrderDoesNotMatter) {
  EXPECT_EQ(test::face_sets(find(test::shuffle_vertices(m_, 12345), RegionMethod::Parts)), test::face_sets(ids_));
}

TEST_F(BearParts, SplittingEveryFaceInFourFindsTheSameRegions) {
  // Region by region, both ways: every region has a partner with IoU >= 0.8.
  const std::vector<int> fine_ids = find(test::split_in_four(m_), RegionMethod::Parts);
  std::string where;
  EXPECT_GE(test::worst_subdivision_iou(ids_, fine_ids, &where), 0.8) << where;
}

TEST(PartFinder, ElkKeepsEveryCapThatTipRegionsDoNotCover) {
  // The elk's nose and head caps have wide spheres (its head is a flat board): their balls fail
  // the filters, so each falls back to its cap. Every cap region that tip regions cover at most
  // half of is therefore in a region here, with all its faces outside the tip regions, whether
  // as a ball or as a cap.
  if (!fs::exists(test::paper_mesh("elk"))) GTEST_SKIP() << "elk.off is absent; run scripts/fetch_paper_meshes.sh";
  const test::TriMesh m = test::to_tri_mesh(read_input_mesh(test::paper_mesh("elk")));
  const std::vector<int> tip_ids = find(m, RegionMethod::Tips), ids = find(m, RegionMethod::Parts);
  int kept = 0;
  for (const std::vector<int>& c : regions_from_face_ids(find(m, RegionMethod::Caps))) {
    std::set<int> covered, free;
    for (int f : c) (tip_ids[static_cast<std::size_t>(f)] >= 0 ? covered : free).insert(f);
    if (area_of(m, covered) > 0.5 * area_of(m, std::set<int>(c.begin(), c.end()))) continue;
    ++kept;
    const int id = ids[static_cast<std::size_t>(*free.begin())];
    ASSERT_GE(id, 0) << "cap region at face " << c.front();
    for (int f : free) EXPECT_EQ(ids[static_cast<std::size_t>(f)], id) << "cap region at face " << c.front();
  }
  EXPECT_GE(kept, 2) << "the nose and the head";
}

TEST(PartFinder, CliMethodPartsWritesTheLibrarysRegions) {
  const fs::path dir = fs::temp_directory_path() / ("sc_part_cli_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string in = std::string(test::MESH_DIR) + "/bumpy_sphere.off", out = (dir / "r.ply").string(),
                    list = (dir / "r.txt").string();
  auto r = test::run_cli({"regions", in, "-o", out, "--method", "parts", "--region-at", "0,0,1"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  r = test::run_cli({"regions", in, "-o", out, "--method", "parts", "--face-list", list});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Mesh mesh = read_input_mesh(in);
  const std::vector<std::vector<int>> got = read_region_file(list, mesh.number_of_faces());
  RegionOptions o;
  o.method = RegionMethod::Parts;
  const std::vector<int> ids = select_spherical_regions(mesh, positions_from_mesh(mesh), o);
  EXPECT_EQ(std::set<std::vector<int>>(got.begin(), got.end()), test::face_sets(ids));
  EXPECT_GE(got.size(), 3u);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace shellcontract
