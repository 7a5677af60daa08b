// Where a Distance hit's contact data are taken (ccd.hpp, CcdResult::contact_time): at a time at
// which the primitives are within the tolerance, the time the hit was decided at. The other CCD
// tests pin toi (a lower bound of the first contact) and the answer; this pins the time the
// weights and the normal belong to, measured here with the distance functions at the linearly
// interpolated positions. For a pair that starts within tau and moves apart, the contact is at
// t = 0: the end of the deciding interval is already farther than tau.
#include <gtest/gtest.h>

#include <cmath>

#include "collision/ccd.hpp"
#include "collision/distance.hpp"

namespace shellcontract {
namespace {

CcdStencil at_time(const CcdStencil& x0, const CcdStencil& x1, double t) {
  CcdStencil x;
  for (int k = 0; k < 4; ++k) x[k] = (1.0 - t) * x0[k] + t * x1[k];
  return x;
}

double distance_at(CcdPrimitive kind, const CcdStencil& x0, const CcdStencil& x1, double t) {
  const CcdStencil x = at_time(x0, x1, t);
  return kind == CcdPrimitive::VertexFace ? point_triangle_distance(x[0], x[1], x[2], x[3])
                                          : segment_segment_distance(x[0], x[1], x[2], x[3]);
}

/// The stencil moved by `offset` at t = 1 for the first primitive (the vertex, or edge a).
CcdStencil moved(CcdPrimitive kind, CcdStencil x, const Vec3& offset) {
  const int split = kind == CcdPrimitive::VertexFace ? 1 : 2;
  for (int k = 0; k < split; ++k) x[k] += offset;
  return x;
}

TEST(CcdContactTime, ADistanceHitsContactDataAreTakenWithinTheTolerance) {
  const double tau = 0.1;
  CcdOptions o;
  o.tolerance = tau;
  const CcdStencil vf = {Vec3(0.25, 0.25, 0.05), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  const CcdStencil ee = {Vec3(-1, 0.3, 0.05), Vec3(1, 0.3, 0.05), Vec3(0, -1, 0), Vec3(0, 1, 0)};
  struct Case {
    CcdPrimitive kind;
    CcdStencil x0;
    Vec3 offset;
  };
  const Case cases[] = {
      {CcdPrimitive::VertexFace, vf, Vec3(0, 0, 1)},  // starts within tau, moves away
      {CcdPrimitive::VertexFace, vf, Vec3(0, 0, 0.3)},
      {CcdPrimitive::EdgeEdge, ee, Vec3(0, 0, 1)},
      {CcdPrimitive::EdgeEdge, ee, Vec3(0.2, 0.1, 0.5)},
  };
  for (const Case& c : cases) {
    const CcdStencil x1 = moved(c.kind, c.x0, c.offset);
    for (bool tighten : {true, false}) {
      o.tighten_toi = tighten;
      const CcdResult r = primitive_ccd(c.kind, c.x0, x1, o);
      SCOPED_TRACE(testing::Message()
                   << (c.kind == CcdPrimitive::VertexFace ? "VF" : "EE") << " offset "
                   << c.offset.transpose() << " tighten " << tighten);
      ASSERT_TRUE(r.hit);
      ASSERT_EQ(r.reason, CcdHitReason::Distance);
      EXPECT_EQ(r.toi, 0.0);
      EXPECT_GE(r.contact_time, r.toi);
      EXPECT_LE(distance_at(c.kind, c.x0, x1, r.contact_time), tau * (1.0 + 1e-12));
    }
  }
}

TEST(CcdContactTime, AnApproachWithinTheToleranceIsReportedWhereTheDistanceIsWithinIt) {
  // Arriving from far: the first contact is at an interior time; the contact data must be at a
  // time at which the pair is within tau, and toi no later than it.
  const double tau = 0.05;
  CcdOptions o;
  o.tolerance = tau;
  const CcdStencil x0 = {Vec3(0.3, 0.2, 1.0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  for (double end_z : {0.02, -0.5}) {
    CcdStencil x1 = x0;
    x1[0].z() = end_z;
    const CcdResult r = vertex_face_ccd(x0, x1, o);
    ASSERT_TRUE(r.hit) << "end z " << end_z;
    EXPECT_LE(distance_at(CcdPrimitive::VertexFace, x0, x1, r.contact_time), tau * (1.0 + 1e-12))
        << "end z " << end_z;
    EXPECT_LE(r.toi, r.contact_time);
    // toi is a lower bound of the first time within tau: z(t) = 1 - (1 - end_z) t reaches tau at
    // t* = (1 - tau) / (1 - end_z).
    EXPECT_LE(r.toi, (1.0 - tau) / (1.0 - end_z) + 1e-12) << "end z " << end_z;
  }
}

}  // namespace
}  // namespace shellcontract
