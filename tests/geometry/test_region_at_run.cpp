// `run --region-at X,Y,Z`: the run plan turns points into the spherical caps
// around the nearest surface points. The nearest face is found here by brute force over every
// triangle (its own closest-point code) and the bumps of bumpy_sphere are labelled in
// meshes/bumpy_sphere.bumps.txt, independently of the finder. Without the option's plan branch
// the run has no region (mark_run_regions returns 0 and every face is -1), and every test fails.
#include <gtest/gtest.h>

#include <algorithm>

#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "mesh/eigen_point_map.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/regions.hpp"
#include "sim/run_plan.hpp"
#include "support/cli_runner.hpp"
#include "support/surface_distance.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

std::string bumpy() { return std::string(test::MESH_DIR) + "/bumpy_sphere.off"; }

/// The labelled bumps (one line of face ids each).
std::vector<std::set<std::size_t>> bumps() {
  std::vector<std::set<std::size_t>> out;
  std::ifstream in(std::string(test::MESH_DIR) + "/bumpy_sphere.bumps.txt");
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::set<std::size_t> b;
    for (std::size_t f; s >> f;) b.insert(f);
    if (!b.empty()) out.push_back(b);
  }
  return out;
}

/// A point outside the surface on the ray from the origin through the bump's face centroid.
Vec3 above_bump(const Mesh& mesh, const Positions& x, const std::set<std::size_t>& bump, double factor) {
  Vec3 c = Vec3::Zero();
  for (std::size_t f : bump)
    for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(FaceIndex(static_cast<unsigned>(f))), mesh))
      c += Vec3(x.row(v.idx())) / 3.0;
  return factor * c / static_cast<double>(bump.size());
}

/// The regions a run with these options would use (the run plan's resolution).
std::vector<int> run_regions(const Mesh& input, const std::string& region_at, std::size_t* count) {
  RunOptions o;
  set_run_option(o, "region-at", region_at);
  resolve_run_options(o);
  Mesh mesh = input;
  *count = mark_run_regions(mesh, o);
  return stored_regions(mesh);
}

std::string point_text(const Vec3& p) {
  return shortest_text(p.x()) + "," + shortest_text(p.y()) + "," + shortest_text(p.z());
}

TEST(RegionAtRun, EachPointGetsTheCapAroundItsNearestSurfacePoint) {
  const Mesh mesh = read_input_mesh(bumpy());
  const Positions x = positions_from_mesh(mesh);
  const std::vector<std::set<std::size_t>> labelled = bumps();
  ASSERT_EQ(labelled.size(), 3u);
  // Just outside bump 0, and a hundred radii away above bump 2: the nearest surface point of
  // the far point is still on bump 2.
  const Vec3 near = above_bump(mesh, x, labelled[0], 1.1), far = above_bump(mesh, x, labelled[2], 100.0);
  std::size_t count = 0;
  const std::vector<int> ids = run_regions(mesh, point_text(near) + ";" + point_text(far), &count);
  EXPECT_EQ(count, 2u);
  const std::size_t fn = test::nearest_face(mesh, x, near).face, ff = test::nearest_face(mesh, x, far).face;
  EXPECT_EQ(ids[fn], 0) << "the first region does not hold the surface point nearest to the first point";
  EXPECT_EQ(ids[ff], 1) << "the second region does not hold the surface point nearest to the far point";
  // And each region is the labelled bump under its point: most of it, no face of another bump.
  for (int r = 0; r < 2; ++r) {
    const std::size_t under = r == 0 ? 0 : 2;
    std::size_t inside = 0, elsewhere = 0;
    for (std::size_t f = 0; f < ids.size(); ++f)
      if (ids[f] == r)
        for (std::size_t b = 0; b < labelled.size(); ++b) (b == under ? inside : elsewhere) += labelled[b].count(f);
    EXPECT_GE(static_cast<double>(inside), 0.8 * static_cast<double>(labelled[under].size())) << "region " << r;
    EXPECT_EQ(elsewhere, 0u) << "region " << r;
  }
}

// On a coarse mesh the nearest surface point's face can be large: the elk's face nearest to this
// point (next to its nose) is 1.5 units away, its nearest corner 13.5 (the diagonal is 270). The
// cap grown from that corner held two of the face's corners but not the face, so the region the
// artist pointed at did not hold the point.
TEST(RegionAtRun, TheRegionHoldsThePointedAtFaceOnACoarseMesh) {
  const Mesh mesh = read_input_mesh(std::string(test::PAPER_MESH_DIR) + "/elk.off");
  const Positions x = positions_from_mesh(mesh);
  const Vec3 p(68.0, -5.0, -86.0);
  std::size_t count = 0;
  const std::vector<int> ids = run_regions(mesh, point_text(p), &count);
  ASSERT_EQ(count, 1u);
  EXPECT_EQ(ids[test::nearest_face(mesh, x, p).face], 0);
}

/// Whether the faces with id `id` form one piece across shared edges.
bool edge_connected(const Mesh& mesh, const std::vector<int>& ids, int id) {
  std::vector<std::size_t> todo;
  std::set<std::size_t> seen;
  for (std::size_t f = 0; f < ids.size() && todo.empty(); ++f)
    if (ids[f] == id) todo.push_back(f), seen.insert(f);
  while (!todo.empty()) {
    const FaceIndex f(static_cast<std::uint32_t>(todo.back()));
    todo.pop_back();
    for (HalfedgeIndex h : CGAL::halfedges_around_face(mesh.halfedge(f), mesh)) {
      const FaceIndex g = mesh.face(mesh.opposite(h));
      if (g != Mesh::null_face() && ids[g.idx()] == id && seen.insert(g.idx()).second) todo.push_back(g.idx());
    }
  }
  return seen.size() == static_cast<std::size_t>(std::count(ids.begin(), ids.end(), id));
}

// The second point lies on a face next to the first region: two of that face's corners are the
// first region's, so the cap grown from its third corner could hold neither it nor its two
// neighbours at that corner. Adding the face alone joined it to the region at one vertex only.
TEST(RegionAtRun, TheAddedPointedAtFaceKeepsTheRegionInOnePiece) {
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/ico2.off");
  const Positions x = positions_from_mesh(mesh);
  const Vec3 p(-0.40424914524207767, -0.08691534297209211, -0.28049156133586095);
  std::size_t count = 0;
  const std::vector<int> ids =
      run_regions(mesh, "-0.023345402668506817,0.28624826916607343,-0.4258135234879707;" + point_text(p), &count);
  ASSERT_EQ(count, 2u);
  EXPECT_EQ(ids[test::nearest_face(mesh, x, p).face], 1);
  EXPECT_TRUE(edge_connected(mesh, ids, 0));
  EXPECT_TRUE(edge_connected(mesh, ids, 1));
}

TEST(RegionAtRun, TheOptionReadsBackAndRefusesMalformedPoints) {
  RunOptions o;
  set_run_option(o, "region-at", "0.1,-2,3e-3;4,5,6");
  ASSERT_EQ(o.region_points.size(), 2u);
  EXPECT_EQ(o.region_points[0], Vec3(0.1, -2, 3e-3));
  RunOptions again;  // what a checkpoint stores reads back to the same points
  set_run_option(again, "region-at", find_run_option("region-at")->get(o));
  EXPECT_EQ(again.region_points, o.region_points);
  for (const char* bad : {"", "1,2", "1,2,3,4", "a,b,c", "1,2,nan", "1,2,inf", "1 2 3", "1,2,3;", ";1,2,3"}) {
    RunOptions r;
    EXPECT_THROW(set_run_option(r, "region-at", bad), UsageError) << "'" << bad << "'";
  }
  RunOptions both;
  set_run_option(both, "region-at", "0,0,1");
  set_run_option(both, "regions", "auto");
  EXPECT_THROW(resolve_run_options(both), UsageError);
}

TEST(RegionAtRun, CliRepeatsTheOptionAndBadPointsWriteNothing) {
  const fs::path dir = fs::temp_directory_path() / ("sc_region_at_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string out = (dir / "out.off").string(), summary = (dir / "s.json").string();
  auto r = test::run_cli({"run", bumpy(), "-o", out, "--region-at", "1,2", "-n", "2", "-q"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("--region-at"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out));
  r = test::run_cli({"run", bumpy(), "-o", out, "--region-at", "0,0,9", "--regions", "auto", "-n", "2", "-q"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_FALSE(fs::exists(out));
  r = test::run_cli({"run", bumpy(), "-o", out, "--summary", summary, "--region-at", "0,0,9", "--region-at=0,0,-9",
                     "-n", "2", "-p", "0", "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(summary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\"regions\": 2"), std::string::npos) << text;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace shellcontract
