// The local contraction's dimple (sim/region_dimple.hpp): its order from the apex, the one-pass
// prefix volumes against the cap volume computed afresh, and the choice of its size.
#include <gtest/gtest.h>

#include "sim/region_dimple.hpp"
#include "support/icosphere_cap.hpp"

namespace shellcontract {
namespace {

/// The level-3 icosphere (perturbed when `noise` > 0) and its faces with a corner above z0.
test::CapScene scene(double z0, double noise, unsigned seed = 7) {
  return test::icosphere_cap(3, z0, noise, seed);
}

TEST(RegionDimple, PrefixVolumesAreTheCapVolumesOfEachPrefix) {
  // The one-pass sums against make_region_cap + cap_volume (rim found afresh, fan from its
  // centroid) for every prefix, on a perturbed cap and in its dimple order and in face order.
  const test::CapScene s = scene(0.3, 0.02);
  const RegionDimple d = make_region_dimple(s.m.x, s.m.faces, s.region);
  ASSERT_EQ(d.order.size(), s.region.size());
  for (const std::vector<int>& order : {d.order, s.region}) {
    const std::vector<double> v = prefix_cap_volumes(s.m.x, s.m.faces, order);
    ASSERT_EQ(v.size(), order.size());
    for (std::size_t k = 1; k <= order.size(); ++k) {
      const RegionCap cap =
          make_region_cap(s.m.faces, std::vector<int>(order.begin(), order.begin() + k));
      EXPECT_NEAR(v[k - 1], cap_volume(s.m.x, cap), 1e-14) << "prefix " << k;
    }
  }
  EXPECT_NEAR(d.prefix_rest_volume.back(), d.whole.rest_volume, 1e-14);
  EXPECT_GT(d.whole.rest_volume, 0.0);
}

TEST(RegionDimple, OrderGrowsFromTheApex) {
  // Unperturbed sphere, cap around +z: the apex is the top vertex (0, 0, 1), the first face
  // touches it, and the face centroids' distances from it never decrease along the order.
  const test::CapScene s = scene(0.5, 0.0);
  const RegionDimple d = make_region_dimple(s.m.x, s.m.faces, s.region);
  Eigen::Index top = 0;
  s.m.x.col(2).maxCoeff(&top);
  const Vec3 apex = s.m.x.row(top);
  ASSERT_NEAR(apex.z(), 1.0, 1e-12);
  const int first = d.order.front();
  EXPECT_TRUE(s.m.faces(first, 0) == top || s.m.faces(first, 1) == top || s.m.faces(first, 2) == top);
  double last = -1.0;
  for (int f : d.order) {
    const Vec3 c = (Vec3(s.m.x.row(s.m.faces(f, 0))) + Vec3(s.m.x.row(s.m.faces(f, 1))) +
                    Vec3(s.m.x.row(s.m.faces(f, 2)))) / 3.0;
    const double r = (c - apex).norm();
    EXPECT_GE(r, last - 1e-15);
    last = r;
  }
  // Growing from the apex, the dimple's cap volume grows with it: each full ring adds volume.
  EXPECT_LT(d.prefix_rest_volume.front(), 1e-15);  // one flat triangle encloses nothing
  EXPECT_GT(d.prefix_rest_volume.back(), d.prefix_rest_volume[d.order.size() / 2]);
}

TEST(RegionDimple, SizeIsTheSmallestPrefixThatHoldsTheVolume) {
  const test::CapScene s = scene(0.3, 0.02, 11);
  RegionDimple d = make_region_dimple(s.m.x, s.m.faces, s.region);
  const int n = static_cast<int>(d.order.size());
  for (double fraction : {0.05, 0.25, 0.5, 0.9, 1.0}) {
    const double volume = fraction * d.whole.rest_volume;
    const int k = dimple_size_for(d, volume);
    ASSERT_GE(k, 1);
    ASSERT_LE(k, n);
    EXPECT_GE(d.prefix_rest_volume[static_cast<std::size_t>(k) - 1], volume - 1e-15);
    for (int j = 1; j < k; ++j) EXPECT_LT(d.prefix_rest_volume[static_cast<std::size_t>(j) - 1], volume);
    set_dimple_size(d, s.m.faces, k);
    EXPECT_EQ(d.size, k);
    EXPECT_NEAR(cap_volume(s.m.x, d.dimple), d.dimple.rest_volume, 1e-14);
  }
  EXPECT_EQ(dimple_size_for(d, 2.0 * d.whole.rest_volume), n);  // more than the region holds
}

TEST(RegionDimple, MirrorImageHasTheOppositeVolume) {
  // The contraction's target for a dimple of rest cap volume V_k is -V_k: its mirror image in
  // the rim's plane (here the rim's mean height), whose cap volume is exactly -V_k (a reflection
  // maps the rim centroid to the reflected centroid and every determinant to minus itself).
  const test::CapScene s = scene(0.5, 0.0);
  RegionDimple d = make_region_dimple(s.m.x, s.m.faces, s.region);
  set_dimple_size(d, s.m.faces, static_cast<int>(d.order.size()) / 2);
  ASSERT_GT(d.dimple.rest_volume, 0.0);
  double rim_z = 0.0;
  for (int r : d.dimple.rim) rim_z += s.m.x(d.dimple.vertices[static_cast<std::size_t>(r)], 2);
  rim_z /= static_cast<double>(d.dimple.rim.size());
  Positions mirrored = s.m.x;
  for (int v : d.dimple.vertices) mirrored(v, 2) = 2.0 * rim_z - s.m.x(v, 2);
  EXPECT_NEAR(cap_volume(mirrored, d.dimple), -d.dimple.rest_volume, 1e-14);
}

TEST(RegionDimple, RestVolumeGoesFromNothingToTheWholeCap) {
  EXPECT_DOUBLE_EQ(dimple_rest_volume(2.0, 0.8, 0.0, 1.0), 0.0);  // ramp not started
  EXPECT_DOUBLE_EQ(dimple_rest_volume(2.0, 0.5, 1.0, 1.0), 1.0);  // 2.0 - 2 * 1.0: no volume left
  EXPECT_DOUBLE_EQ(dimple_rest_volume(2.0, 1.0, 1.0, 1.0), 2.0);  // the whole cap's mirror image
  EXPECT_DOUBLE_EQ(dimple_rest_volume(2.0, 0.0, 1.0, 0.5), 0.0);  // off
  // A contracted shell (rho 0.5): the mirrored dimple -0.5 V_k takes 2 * 0.1 * 2.0 off the cap's
  // share 1.0 when V_k = 0.4; the whole cap at most.
  EXPECT_DOUBLE_EQ(dimple_rest_volume(2.0, 0.1, 1.0, 0.5), 0.4);
  EXPECT_DOUBLE_EQ(dimple_rest_volume(2.0, 1.0, 1.0, 0.5), 2.0);
  EXPECT_DOUBLE_EQ(dimple_rest_volume(2.0, 0.3, 1.0, 0.0), 2.0);  // no shell left: the whole cap
}

}  // namespace
}  // namespace shellcontract
