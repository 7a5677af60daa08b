// The default dimple (docs/math/region-mirror.md, sections 3 and 5): the mirror is carried by the
// shell's frame away from the regions, not by its own rim (which the dimple pulls in), its crease
// ring is left to the solver, and its image is a mould that a deeper vertex stays below. In a run
// at the defaults, bumpy_sphere's bumps then sink locally by the local contraction's own measures.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "shellcontract/mesh.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/regions.hpp"
#include "shellcontract/run.hpp"
#include "sim/region_mirror.hpp"
#include "sim/rest_state.hpp"
#include "support/flat_rim_cap.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

/// test::flat_rim_cap's cap, followed by four points off the cap that stand for the
/// shell away from the region (no face uses them).
struct CapAndShell {
  Positions x;
  Faces faces;
  std::vector<int> region;
  std::vector<int> away;  ///< the four extra points
};

CapAndShell cap_and_shell(int rings = 4, int n = 12, double theta = 0.9) {
  const test::FlatRimCap cap = test::flat_rim_cap(rings, n, theta);
  CapAndShell c;
  const auto cap_vertices = static_cast<int>(cap.x.rows());
  c.x.resize(cap_vertices + 4, 3);
  c.x.topRows(cap_vertices) = cap.x;
  c.x.row(cap_vertices + 0) << 0.0, 0.0, -1.0;
  c.x.row(cap_vertices + 1) << 1.0, 0.0, -0.5;
  c.x.row(cap_vertices + 2) << -0.5, 0.9, -0.4;
  c.x.row(cap_vertices + 3) << -0.5, -0.9, -0.2;
  for (int k = 0; k < 4; ++k) c.away.push_back(cap_vertices + k);
  c.faces = cap.faces;
  c.region = cap.region;
  return c;
}

/// The reflection of a rest point through the flat rim's plane z = cos theta.
Vec3 rest_image(const Positions& x, int v, double rim_z) {
  Vec3 p = x.row(v);
  p.z() = 2.0 * rim_z - p.z();
  return p;
}

TEST(RegionMirrorFrame, TheShellFrameDoesNotFollowARimPulledIn) {
  // The dimple pulls its rim in; a mirror carried by the rim's fit shrinks with it (the scale
  // falls), which pulls the rim further: the feedback that made the rim-carried mirror creep.
  // The shell's frame, fitted to the vertices away from the region, is the identity here, so
  // every interior vertex goes to its rest image whatever the rim did.
  const CapAndShell c = cap_and_shell();
  const RegionCap cap = make_region_cap(c.faces, c.region);
  const RegionMirror m = make_region_mirror(c.x, cap);
  ASSERT_EQ(m.fallback, MirrorFallback::None) << mirror_fallback_name(m.fallback);
  Positions pulled = c.x;
  for (int r : cap.rim) {
    const int v = cap.vertices[static_cast<std::size_t>(r)];
    const Vec3 p = c.x.row(v);
    pulled.row(v) = Vec3(0.8 * p.x(), 0.8 * p.y(), p.z()).transpose();  // rim drawn inward
  }
  const std::optional<Similarity> frame = shell_frame(c.x, pulled, c.away);
  ASSERT_TRUE(frame.has_value());
  EXPECT_NEAR(frame->scale, 1.0, 1e-12);
  EXPECT_NEAR((frame->rotation - Mat3::Identity()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(frame->translation.norm(), 0.0, 1e-12);
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(c.x.rows());
  Positions in_shell = pulled, on_rim = pulled;
  ASSERT_TRUE(apply_region_mirror_in(in_shell, cap, m, *frame, w, {}, MirrorStep{}));
  ASSERT_TRUE(apply_region_mirror(on_rim, cap, m, w, {}, 1.0));
  const double rim_z = c.x(cap.vertices[static_cast<std::size_t>(cap.rim.front())], 2);
  double rim_carried_off = 0.0;
  for (int k : m.moved) {
    const int v = cap.vertices[static_cast<std::size_t>(k)];
    EXPECT_NEAR((Vec3(in_shell.row(v)) - rest_image(c.x, v, rim_z)).norm(), 0.0, 1e-12);
    rim_carried_off =
        std::max(rim_carried_off, (Vec3(on_rim.row(v)) - rest_image(c.x, v, rim_z)).norm());
  }
  EXPECT_GT(rim_carried_off, 0.05) << "the rim's fit should have followed the rim in";
}

TEST(RegionMirrorFrame, TheCreaseRingIsLeftToTheSolverAndTheRestIsStrainFree) {
  // Four rings, the last the rim: the third ring shares faces with the rim (the crease ring);
  // the apex and the first two rings lie beyond it. With free_crease the crease ring stays where
  // it is and every other interior vertex lands on its image, so every edge between two of them
  // keeps its rest length (a reflection) up to rounding.
  const CapAndShell c = cap_and_shell(4, 12);
  const RegionCap cap = make_region_cap(c.faces, c.region);
  const RegionMirror m = make_region_mirror(c.x, cap);
  ASSERT_EQ(m.crease.size(), m.moved.size());
  std::set<int> crease;
  for (std::size_t i = 0; i < m.moved.size(); ++i)
    if (m.crease[i]) crease.insert(cap.vertices[static_cast<std::size_t>(m.moved[i])]);
  std::set<int> third_ring;
  for (int i = 0; i < 12; ++i) third_ring.insert(1 + 2 * 12 + i);
  EXPECT_EQ(crease, third_ring);
  Positions x = c.x;
  const Similarity identity;
  MirrorStep step;
  step.free_crease = true;
  ASSERT_TRUE(apply_region_mirror_in(x, cap, m, identity, Eigen::VectorXd::Ones(x.rows()), {},
                                     step));
  const double rim_z = c.x(cap.vertices[static_cast<std::size_t>(cap.rim.front())], 2);
  std::vector<char> moved(static_cast<std::size_t>(x.rows()), 0);
  for (int k : m.moved) {
    const int v = cap.vertices[static_cast<std::size_t>(k)];
    if (crease.count(v)) {
      EXPECT_EQ(x.row(v), c.x.row(v)) << "crease vertex " << v;
    } else {
      moved[static_cast<std::size_t>(v)] = 1;
      EXPECT_NEAR((Vec3(x.row(v)) - rest_image(c.x, v, rim_z)).norm(), 0.0, 1e-12);
    }
  }
  int checked = 0;
  for (Eigen::Index j = 0; j < c.faces.rows(); ++j)
    for (int k = 0; k < 3; ++k) {
      const int a = c.faces(j, k), b = c.faces(j, (k + 1) % 3);
      if (!moved[static_cast<std::size_t>(a)] || !moved[static_cast<std::size_t>(b)]) continue;
      EXPECT_NEAR((x.row(a) - x.row(b)).norm(), (c.x.row(a) - c.x.row(b)).norm(), 1e-12);
      ++checked;
    }
  EXPECT_GT(checked, 12);
}

TEST(RegionMirrorFrame, ADimpleOfOneRingHasNoCreaseToFree) {
  // Two rings: the apex is beyond the crease ring, so it moves. One ring: the apex itself shares
  // faces with the rim, nothing lies beyond it, so no vertex is flagged and the apex still sinks
  // (otherwise the dimple's first frames, a few faces around the apex, would not sink at all).
  const CapAndShell one = cap_and_shell(1, 8);
  const RegionCap cap = make_region_cap(one.faces, one.region);
  const RegionMirror m = make_region_mirror(one.x, cap);
  ASSERT_EQ(m.moved.size(), 1u);
  EXPECT_EQ(m.crease, std::vector<char>{0});
  Positions x = one.x;
  MirrorStep step;
  step.free_crease = true;
  ASSERT_TRUE(apply_region_mirror_in(x, cap, m, Similarity{}, Eigen::VectorXd::Ones(x.rows()), {},
                                     step));
  EXPECT_LT(x(0, 2), one.x(0, 2) - 0.1);
}

TEST(RegionMirrorFrame, TheMouldLeavesADeeperVertexAlone) {
  // one_sided: a vertex pushed below its image (a load sank it deeper) stays; one above it is
  // moved onto it. Without the rule the mirror would lift what the region load sank (at the
  // default pressure the bumps then sink less than twice as far as without the contraction).
  const CapAndShell c = cap_and_shell();
  const RegionCap cap = make_region_cap(c.faces, c.region);
  const RegionMirror m = make_region_mirror(c.x, cap);
  const double rim_z = c.x(cap.vertices[static_cast<std::size_t>(cap.rim.front())], 2);
  Positions x = c.x;
  const Vec3 deep = rest_image(c.x, 0, rim_z) - Vec3(0.0, 0.0, 0.05);
  x.row(0) = deep.transpose();  // the apex, below its image
  MirrorStep step;
  step.one_sided = true;
  ASSERT_TRUE(apply_region_mirror_in(x, cap, m, Similarity{}, Eigen::VectorXd::Ones(x.rows()), {},
                                     step));
  EXPECT_EQ(Vec3(x.row(0)), deep);
  const int first_ring = 1;
  EXPECT_NEAR((Vec3(x.row(first_ring)) - rest_image(c.x, first_ring, rim_z)).norm(), 0.0, 1e-12);
}

/// Per region, the mean inward displacement of its vertices along the rest vertex normal; and
/// the mean displacement of the vertices outside the regions and their one-ring band.
struct Locality {
  std::vector<double> sink;
  double rest = 0.0;
};

Locality measure(const Mesh& mesh, const Positions& end, const std::vector<std::vector<int>>& regs) {
  const Positions x0 = positions_from_mesh(mesh);
  const Faces f = faces_array(mesh);
  Positions normal = Positions::Zero(x0.rows(), 3);
  for (Eigen::Index j = 0; j < f.rows(); ++j) {
    const Vec3 n = (Vec3(x0.row(f(j, 1))) - Vec3(x0.row(f(j, 0))))
                       .cross(Vec3(x0.row(f(j, 2))) - Vec3(x0.row(f(j, 0))));
    for (int k = 0; k < 3; ++k) normal.row(f(j, k)) += n.transpose();
  }
  Locality out;
  std::vector<char> in(static_cast<std::size_t>(x0.rows()), 0);
  for (const auto& r : regs) {
    std::set<int> vs;
    for (int j : r)
      for (int k = 0; k < 3; ++k) vs.insert(f(j, k)), in[static_cast<std::size_t>(f(j, k))] = 1;
    double s = 0.0;
    for (int v : vs) s -= (end.row(v) - x0.row(v)).dot(normal.row(v).normalized());
    out.sink.push_back(s / static_cast<double>(vs.size()));
  }
  std::vector<char> band = in;
  for (Eigen::Index j = 0; j < f.rows(); ++j)
    if (in[static_cast<std::size_t>(f(j, 0))] || in[static_cast<std::size_t>(f(j, 1))] ||
        in[static_cast<std::size_t>(f(j, 2))])
      for (int k = 0; k < 3; ++k) band[static_cast<std::size_t>(f(j, k))] = 1;
  int n = 0;
  for (Eigen::Index i = 0; i < x0.rows(); ++i)
    if (!band[static_cast<std::size_t>(i)]) out.rest += (end.row(i) - x0.row(i)).norm(), ++n;
  if (n > 0) out.rest /= n;
  return out;
}

TEST(RegionMirrorFrame, BumpsSinkLocallyAtTheDefaults) {
  // The local contraction's own bar, on bumpy_sphere's three bumps (the face-list file) with no
  // option but the regions: at -p 0 the smallest bump sinks at least 1 % of the bounding-box
  // diagonal (the mean over its vertices along the rest normals), the rest of the shell moves at
  // most a tenth of that, no new self-intersection; under the default pressure every bump sinks
  // at least twice as far as with --inward none. Each part of the default is needed (checked by
  // switching it off in Simulator::apply_region_contraction): it fails with the former default
  // --dimple volume (rest / smallest sink 0.15), with the rim's fit for the shell's frame (0.105),
  // with the crease ring placed (0.102), and with the mould off (0.114, and a bump 0.74x at the
  // default pressure).
  const std::string dir = test::MESH_DIR;
  const Mesh mesh = read_input_mesh(dir + "/bumpy_sphere.off");
  const std::string bumps = dir + "/bumpy_sphere.bumps.txt";
  const std::vector<std::vector<int>> regs = read_region_file(bumps, mesh.number_of_faces());
  const Positions x0 = positions_from_mesh(mesh);
  const double diag = (x0.colwise().maxCoeff() - x0.colwise().minCoeff()).norm();
  auto run = [&](const std::vector<std::pair<std::string, std::string>>& extra) {
    RunOptions o;
    set_run_option(o, "regions", bumps);
    set_run_option(o, "validate", "end");
    for (const auto& [k, v] : extra) set_run_option(o, k, v);
    RunResult r = run_contraction(mesh, o);
    EXPECT_EQ(r.status, RunStatus::Completed) << r.message;
    EXPECT_EQ(r.new_intersections, 0);
    return r;
  };
  const RunResult still_run = run({{"pressure", "0"}});
  const Locality still = measure(mesh, still_run.positions, regs);
  ASSERT_EQ(still.sink.size(), 3u);
  // The run's own rest-of-the-shell figure (normalized units: the diagonal is 1), which the
  // other locality tests and --summary's outside_region_displacement read, is this measure's.
  EXPECT_NEAR(still_run.outside_region_displacement, still.rest / diag, 1e-9 * still.rest / diag);
  const double smallest = *std::min_element(still.sink.begin(), still.sink.end());
  EXPECT_GE(smallest, 0.01 * diag);
  EXPECT_LE(still.rest, 0.1 * smallest) << "rest " << still.rest << ", smallest sink " << smallest;
  const Locality on = measure(mesh, run({}).positions, regs);
  const Locality off = measure(mesh, run({{"inward", "none"}}).positions, regs);
  for (std::size_t k = 0; k < 3; ++k)
    EXPECT_GE(on.sink[k], 2.0 * off.sink[k]) << "bump " << k;
}

}  // namespace
}  // namespace shellcontract
