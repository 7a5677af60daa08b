// What --region-shrink S sets (docs/math/local-contraction.md, sections 3-4): the dimple around
// the apex holding S of the region's rest cap volume, sunk to its mirror image. The image takes
// twice the dimple's volume off the region only where the dimple's rim is a plane section; the
// mirror moves the interior vertices alone, so on a ragged rim (a prefix of faces of a coarse
// mesh) it takes less. Checked against a volume computed another way (prisms over the rim plane).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "sim/region_dimple.hpp"
#include "sim/region_mirror.hpp"
#include "support/icosphere_cap.hpp"

namespace shellcontract {
namespace {

constexpr double PI = 3.14159265358979323846;

/// A polar cap of the unit sphere: the pole and `rings` rings of `n` vertices at polar angles
/// 0.12, 0.24, ... (each ring turned half a step from the last), joined by bands of triangles,
/// counter-clockwise from outside. Every ring is level, so the cap of the first j bands has a
/// rim that is a plane section.
struct RingCap {
  Positions x;
  Faces faces;
  std::vector<int> region;
};

RingCap ring_cap(int rings, int n) {
  RingCap c;
  c.x.resize(1 + rings * n, 3);
  c.x.row(0) = Vec3(0.0, 0.0, 1.0);
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < n; ++i) {
      const double theta = 0.12 * (j + 1), phi = 2.0 * PI * (i + 0.5 * j) / n;
      c.x.row(1 + j * n + i) =
          Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    }
  std::vector<std::array<int, 3>> f;
  for (int i = 0; i < n; ++i) f.push_back({0, 1 + i, 1 + (i + 1) % n});
  for (int j = 0; j + 1 < rings; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = 1 + j * n + i, b = 1 + j * n + (i + 1) % n;
      const int c0 = 1 + (j + 1) * n + i, c1 = 1 + (j + 1) * n + (i + 1) % n;
      f.push_back({a, c0, c1});
      f.push_back({a, c1, b});
    }
  c.faces.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t k = 0; k < f.size(); ++k) {
    for (int m = 0; m < 3; ++m)
      c.faces(static_cast<Eigen::Index>(k), m) = f[k][static_cast<std::size_t>(m)];
    c.region.push_back(static_cast<int>(k));
  }
  return c;
}

/// The volume between `faces` and the level plane z = level under them: the prisms over their
/// projections onto the xy-plane (signed area times mean height). Not the fan of cap_volume.
double prism_volume(const Positions& x, const Faces& faces, const std::vector<int>& region,
                    double level) {
  double v = 0.0;
  for (int f : region) {
    const Vec3 a = x.row(faces(f, 0)), b = x.row(faces(f, 1)), d = x.row(faces(f, 2));
    const double area =
        0.5 * ((b.x() - a.x()) * (d.y() - a.y()) - (d.x() - a.x()) * (b.y() - a.y()));
    v += area * ((a.z() + b.z() + d.z()) / 3.0 - level);
  }
  return v;
}

/// `x` with the dimple's interior vertices on their rest mirror images (what the mirror places
/// at -p 0, where the shell's frame is the identity); its rim and the rest of the region stay.
Positions placed(const Positions& x, const RegionDimple& d, const RegionMirror& m) {
  Positions y = x;
  for (std::size_t k = 0; k < m.moved.size(); ++k)
    y.row(d.dimple.vertices[static_cast<std::size_t>(m.moved[k])]) = m.image[k] + m.rest_centre;
  return y;
}

/// The spread of the dimple's rim heights along `axis`.
double rim_spread(const Positions& x, const RegionCap& cap, const Vec3& axis) {
  double lo = 1e300, hi = -1e300;
  for (int r : cap.rim) {
    const double h = Vec3(x.row(cap.vertices[static_cast<std::size_t>(r)])).dot(axis);
    lo = std::min(lo, h), hi = std::max(hi, h);
  }
  return hi - lo;
}

TEST(RegionShrinkScale, AMirroredDimpleWithAPlaneRimTakesTwiceItsShareOff) {
  // Six bands; S picks the dimple that ends at band 2, 4 or 6 (S = that cap's share of the
  // region's volume, the rim a level ring): its image takes 2 S of the region's cap volume off,
  // so the region's cap is (1 - 2S) of its rest volume, with the volumes taken by prisms.
  const int rings = 6, n = 16;
  const RingCap c = ring_cap(rings, n);
  RegionDimple d = make_region_dimple(c.x, c.faces, c.region);
  ASSERT_EQ(d.limit, static_cast<int>(d.order.size()));  // a level rim: not cut
  const double rim_z = std::cos(0.12 * rings);
  const double whole = prism_volume(c.x, c.faces, c.region, rim_z);
  ASSERT_GT(whole, 0.0);
  EXPECT_NEAR(cap_volume(c.x, d.whole), whole, 1e-12 * whole);
  for (int bands : {2, 4, 6}) {
    const int faces = n * (2 * bands - 1);
    const std::vector<int> inner(d.order.begin(), d.order.begin() + faces);
    const double share = prism_volume(c.x, c.faces, inner, std::cos(0.12 * bands)) / whole;
    const double S = share * (1.0 - 1e-12);  // the prefix's own volume, not one face more
    set_dimple_size(d, c.faces,
                    dimple_size_for(d, dimple_rest_volume(d.whole.rest_volume, S, 1.0, 1.0)));
    ASSERT_EQ(d.size, faces) << bands << " bands";
    ASSERT_LT(rim_spread(c.x, d.dimple, Vec3::UnitZ()), 1e-12);
    const RegionMirror m = make_region_mirror(c.x, d.dimple);
    ASSERT_EQ(m.fallback, MirrorFallback::None);
    const Positions y = placed(c.x, d, m);
    EXPECT_NEAR(cap_volume(y, d.whole), (1.0 - 2.0 * S) * whole, 1e-9 * whole) << bands << " bands";
    EXPECT_NEAR(cap_volume(y, d.dimple), -d.dimple.rest_volume, 1e-9 * whole);
  }
}

TEST(RegionShrinkScale, OnARaggedRimTheImageTakesLessThanTwiceTheDimple) {
  // A small cap of a coarse icosphere (52 faces, like a bump of meshes/bumpy_sphere.off): a
  // prefix of faces from the apex has a rim ragged by about an edge. The dimple still holds at
  // least S of the region's volume (its target, -V_k, takes at least 2 S off), but its image,
  // the interior vertices mirrored and the rim kept, takes less than 2 V_k off; the region loses
  // what the dimple loses (the faces between the two rims stay).
  const test::CapScene s = test::icosphere_cap(2, 0.8, 0.0, 7);
  RegionDimple d = make_region_dimple(s.m.x, s.m.faces, s.region);
  const double whole = d.whole.rest_volume;
  ASSERT_GT(whole, 0.0);
  for (double S : {0.25, 0.5, 0.7}) {
    set_dimple_size(d, s.m.faces, dimple_size_for(d, dimple_rest_volume(whole, S, 1.0, 1.0)));
    ASSERT_LT(d.size, static_cast<int>(d.order.size()));
    EXPECT_GE(d.dimple.rest_volume, S * whole);
    ASSERT_GT(rim_spread(s.m.x, d.dimple, d.axis), 0.05);  // not a plane section
    const RegionMirror m = make_region_mirror(s.m.x, d.dimple);
    ASSERT_EQ(m.fallback, MirrorFallback::None);
    const Positions y = placed(s.m.x, d, m);
    const double dimple_now = cap_volume(y, d.dimple), region_now = cap_volume(y, d.whole);
    EXPECT_GT(dimple_now, -d.dimple.rest_volume + 0.05 * d.dimple.rest_volume) << "S " << S;
    EXPECT_NEAR(region_now - whole, dimple_now - d.dimple.rest_volume, 1e-12 * whole) << "S " << S;
    // "0.5 takes a bump's whole volume off" holds for the target, not for the placed shape.
    if (S == 0.5) {
      EXPECT_GT(region_now, 0.1 * whole);
    }
  }
}

}  // namespace
}  // namespace shellcontract
