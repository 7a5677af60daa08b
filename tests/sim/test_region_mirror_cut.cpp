// The dimple's cut (sim/region_dimple.hpp, docs/math/region-mirror.md section 4): a region whose
// rim is not a plane section sinks only the part above a plane cut, so its mirror image meets the
// shell along a flat rim. On a region with a rim far off any plane (bear's head) the whole-region
// dimple dents the shell around it; the cut one leaves it in place.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "shellcontract/mesh.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/run.hpp"
#include "sim/region_dimple.hpp"
#include "sim/rest_state.hpp"
#include "support/icosphere_cap.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

double height(const Positions& x, int v, const Vec3& axis) { return Vec3(x.row(v)).dot(axis); }

TEST(RegionMirrorCut, TheDimpleStopsAtThePlaneCut) {
  // An icosphere region whose rim is bent: the faces with a corner above z = 0.2 + 0.8 x^2, so
  // its rim rises by about 0.5 over its width, several times CUT_TOLERANCE edges (about 0.07).
  test::CapScene s = test::icosphere_cap(4, 2.0, 0.0, 1);
  for (Eigen::Index j = 0; j < s.m.faces.rows(); ++j)
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = s.m.x.row(s.m.faces(j, k));
      if (p.z() > 0.2 + 0.8 * p.x() * p.x()) {
        s.region.push_back(static_cast<int>(j));
        break;
      }
    }
  const RegionDimple d = make_region_dimple(s.m.x, s.m.faces, s.region);
  const int n = static_cast<int>(d.order.size());
  ASSERT_EQ(n, static_cast<int>(s.region.size()));
  ASSERT_GT(d.limit, 0);
  ASSERT_LT(d.limit, n);  // the rim's low sides lie below the cut
  ASSERT_NEAR(d.axis.norm(), 1.0, 1e-12);

  // The cut: the region's highest rim vertex along the axis, lowered by CUT_TOLERANCE edges.
  double edge = 0.0, longest = 0.0;
  for (int f : d.order)
    for (int k = 0; k < 3; ++k) {
      const double l = (Vec3(s.m.x.row(s.m.faces(f, (k + 1) % 3))) - Vec3(s.m.x.row(s.m.faces(f, k)))).norm();
      edge += l;
      longest = std::max(longest, l);
    }
  edge /= 3.0 * n;
  double top = -std::numeric_limits<double>::infinity();
  for (int r : d.whole.rim) top = std::max(top, height(s.m.x, d.whole.vertices[static_cast<std::size_t>(r)], d.axis));
  const double cut = top - CUT_TOLERANCE * edge;
  for (int i = 0; i < n; ++i) {
    const int f = d.order[static_cast<std::size_t>(i)];
    const double lowest = std::min({height(s.m.x, s.m.faces(f, 0), d.axis), height(s.m.x, s.m.faces(f, 1), d.axis),
                                    height(s.m.x, s.m.faces(f, 2), d.axis)});
    if (i < d.limit)
      EXPECT_GE(lowest, cut) << "face " << i << " of the limit lies below the cut";
    else
      EXPECT_LT(lowest, cut) << "face " << i << " past the limit lies above the cut";
  }
  // The dimple grows no further than the limit, and the limit's rim is a plane section: all its
  // vertices lie within an edge of the cut plus the tolerance, where the whole region's rim spans
  // several edges.
  EXPECT_EQ(dimple_size_for(d, 2.0 * d.whole.rest_volume), d.limit);
  const RegionCap limit = make_region_cap(s.m.faces, std::vector<int>(d.order.begin(), d.order.begin() + d.limit));
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int r : limit.rim) {
    const double h = height(s.m.x, limit.vertices[static_cast<std::size_t>(r)], d.axis);
    lo = std::min(lo, h);
    hi = std::max(hi, h);
  }
  EXPECT_LE(hi - lo, CUT_TOLERANCE * edge + longest);
  double whole_lo = std::numeric_limits<double>::infinity(), whole_hi = -whole_lo;
  for (int r : d.whole.rim) {
    const double h = height(s.m.x, d.whole.vertices[static_cast<std::size_t>(r)], d.axis);
    whole_lo = std::min(whole_lo, h);
    whole_hi = std::max(whole_hi, h);
  }
  EXPECT_GT(whole_hi - whole_lo, CUT_TOLERANCE * edge);
  EXPECT_GT(d.prefix_rest_volume[static_cast<std::size_t>(d.limit) - 1], 0.0);
}

TEST(RegionMirrorCut, ARotatedRegionGetsTheRotatedCut) {
  // A bent and leaning rim (corners above z = 0.1 + 0.4 x + 0.8 x^2), on the icosphere and on
  // the same icosphere rotated about a skew axis: the same limit, the same faces above the cut,
  // and the rotated axis. (Not the same order: rounding orders equal heights.) The tilts tried start from the direction in
  // which the rim rises, not from a coordinate axis. This test also passes with a coordinate-axis
  // start (checked): it guards the invariance, it does not single out the start.
  test::CapScene s = test::icosphere_cap(4, 2.0, 0.0, 1);
  for (Eigen::Index j = 0; j < s.m.faces.rows(); ++j)
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = s.m.x.row(s.m.faces(j, k));
      if (p.z() > 0.1 + 0.4 * p.x() + 0.8 * p.x() * p.x()) {
        s.region.push_back(static_cast<int>(j));
        break;
      }
    }
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
  const Positions turned = (s.m.x * R.transpose()).eval();
  const RegionDimple a = make_region_dimple(s.m.x, s.m.faces, s.region);
  const RegionDimple b = make_region_dimple(turned, s.m.faces, s.region);
  ASSERT_LT(a.limit, static_cast<int>(a.order.size()));  // the cut applies
  EXPECT_EQ(a.limit, b.limit);
  std::vector<int> above_a(a.order.begin(), a.order.begin() + a.limit);
  std::vector<int> above_b(b.order.begin(), b.order.begin() + std::min(b.limit, static_cast<int>(b.order.size())));
  std::sort(above_a.begin(), above_a.end());
  std::sort(above_b.begin(), above_b.end());
  EXPECT_EQ(above_a, above_b);
  EXPECT_LE((R * a.axis - b.axis).norm(), 1e-9);
}

TEST(RegionMirrorCut, AFlatRimIsNotCut) {
  // A cap cut by a plane (corners above z = 0.5 on the unit sphere): its rim is ragged by about
  // an edge, within the tolerance, so no face is cut away, the axis is the cap's normal, and
  // the dimple grows from the apex (the first face holds the top vertex).
  const test::CapScene s = test::icosphere_cap(3, 0.5, 0.0, 1);
  const RegionDimple d = make_region_dimple(s.m.x, s.m.faces, s.region);
  EXPECT_EQ(d.limit, static_cast<int>(d.order.size()));
  EXPECT_GT(d.axis.z(), 0.99);
  Eigen::Index top = 0;
  s.m.x.col(2).maxCoeff(&top);
  const int first = d.order.front();
  EXPECT_TRUE(s.m.faces(first, 0) == top || s.m.faces(first, 1) == top || s.m.faces(first, 2) == top);
  EXPECT_EQ(dimple_size_for(d, 2.0 * d.whole.rest_volume), static_cast<int>(d.order.size()));
}

TEST(RegionMirrorCut, BearsHeadSinksLocally) {
  // Bear's head (lab/regions/labels.py: the faces whose centroid lies within 0.3 of
  // (0, 0.55, 0), less the ears' balls of 0.17 around the highest vertex on either side of
  // |x| = 0.15) is 16 % of the surface and its rim is about 17 edges off any plane. At -p 0 it
  // sinks at least 1 % of the diagonal while the rest of the shell (outside the region and its
  // one-ring band) moves at most a tenth of that, with no new self-intersection. Mirroring the
  // whole region's dimple (no cut) moves the rest by a third of the sink.
  const std::string path = std::string(test::PAPER_MESH_DIR) + "/bear.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "no " << path << " (scripts/fetch_paper_meshes.sh)";
  const Mesh mesh = read_input_mesh(path);
  const Positions x = positions_from_mesh(mesh);
  const Faces f = faces_array(mesh);
  Vec3 ear[2];
  for (int side = 0; side < 2; ++side) {
    double best = -std::numeric_limits<double>::infinity();
    for (Eigen::Index i = 0; i < x.rows(); ++i)
      if ((side == 0 ? x(i, 0) < -0.15 : x(i, 0) > 0.15) && x(i, 1) > best) best = x(i, 1), ear[side] = x.row(i);
  }
  const std::string list = testing::TempDir() + "bear_head_cut.txt";
  {
    std::ofstream out(list);
    for (Eigen::Index j = 0; j < f.rows(); ++j) {
      const Vec3 c = (Vec3(x.row(f(j, 0))) + Vec3(x.row(f(j, 1))) + Vec3(x.row(f(j, 2)))) / 3.0;
      if ((c - ear[0]).norm() <= 0.17 || (c - ear[1]).norm() <= 0.17) continue;
      if ((c - Vec3(0.0, 0.55, 0.0)).norm() <= 0.30) out << j << ' ';
    }
    out << '\n';
  }
  RunOptions o;
  set_run_option(o, "pressure", "0");
  set_run_option(o, "frames", "100");
  set_run_option(o, "regions", list);
  set_run_option(o, "validate", "end");
  const RunResult r = run_contraction(mesh, o);
  ASSERT_EQ(r.status, RunStatus::Completed) << r.message;
  EXPECT_EQ(r.regions, 1u);
  EXPECT_EQ(r.new_intersections, 0);
  EXPECT_GE(r.region_inward_displacement, 0.01);
  EXPECT_LE(r.outside_region_displacement, 0.1 * r.region_inward_displacement)
      << "sink " << r.region_inward_displacement << ", rest " << r.outside_region_displacement;
}

}  // namespace
}  // namespace shellcontract
