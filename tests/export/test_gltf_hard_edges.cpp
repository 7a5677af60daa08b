// The .glb of a run keeps the input's hard edges (docs/design/export.md, "Hard edges"): a cube
// whose sides have their own normals (an OBJ's per-face `vn`, a PLY's or glTF's vertices split
// per side) is contracted on its 8 welded vertices, and its glTF animation has a vertex per
// corner of a side, each with its side's normal in every frame; a cube with smooth normals, or
// none, is not split. Runs the built CLI (a few frames of a 12-triangle cube).
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "export_fixtures.hpp"
#include "gltf_reader.hpp"
#include "shellcontract/export.hpp"
#include "support/cli_runner.hpp"
#include "support/gltf_files.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

/// The unit cube's corners and its sides: four corners counter-clockwise seen from outside, and
/// the side's outward normal.
const std::array<std::array<float, 3>, 8> kCorner = {
    {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}};
struct Side {
  std::array<int, 4> corner;
  std::array<float, 3> normal;
};
const std::array<Side, 6> kSide = {{{{0, 3, 2, 1}, {0, 0, -1}},
                                    {{4, 5, 6, 7}, {0, 0, 1}},
                                    {{0, 1, 5, 4}, {0, -1, 0}},
                                    {{2, 3, 7, 6}, {0, 1, 0}},
                                    {{0, 4, 7, 3}, {-1, 0, 0}},
                                    {{1, 2, 6, 5}, {1, 0, 0}}}};

std::string cube_positions_obj() {
  std::string s;
  for (const auto& c : kCorner)
    s += "v " + std::to_string(c[0]) + " " + std::to_string(c[1]) + " " + std::to_string(c[2]) +
         "\n";
  return s;
}

/// Flat-shaded: one `vn` per side, each side's corners use it (Blender's export of a cube), or
/// (`per_corner`) one line per face corner, each with its side's value.
std::string flat_cube_obj(bool per_corner = false) {
  std::string s = cube_positions_obj();
  for (const Side& f : kSide)
    for (int k = 0; k < (per_corner ? 4 : 1); ++k)
      s += "vn " + std::to_string(f.normal[0]) + " " + std::to_string(f.normal[1]) + " " +
           std::to_string(f.normal[2]) + "\n";
  for (std::size_t i = 0; i < kSide.size(); ++i) {
    s += "f";
    for (std::size_t k = 0; k < 4; ++k)
      s += " " + std::to_string(kSide[i].corner[k] + 1) + "//" +
           std::to_string(per_corner ? 4 * i + k + 1 : i + 1);
    s += "\n";
  }
  return s;
}

/// The smooth normal of a cube's corner: from the centre.
std::string smooth_vn(const std::array<float, 3>& c) {
  const double r = std::sqrt(3.0) / 2.0;
  return "vn " + std::to_string((c[0] - 0.5) / r) + " " + std::to_string((c[1] - 0.5) / r) + " " +
         std::to_string((c[2] - 0.5) / r) + "\n";
}

/// Smooth: one `vn` per position (from the centre), `with_normals` false: no `vn` at all;
/// `per_corner`: the same values, one line per face corner (as some exporters write them).
std::string smooth_cube_obj(bool with_normals, bool per_corner = false) {
  std::string s = cube_positions_obj();
  if (with_normals && !per_corner)
    for (const auto& c : kCorner) s += smooth_vn(c);
  if (per_corner)
    for (const Side& f : kSide)
      for (const int c : f.corner) s += smooth_vn(kCorner[static_cast<std::size_t>(c)]);
  for (std::size_t i = 0; i < kSide.size(); ++i) {
    s += "f";
    for (std::size_t k = 0; k < 4; ++k) {
      const int c = kSide[i].corner[k];
      s += " " + std::to_string(c + 1);
      if (with_normals || per_corner)
        s += "//" + std::to_string(per_corner ? 4 * i + k + 1 : static_cast<std::size_t>(c) + 1);
    }
    s += "\n";
  }
  return s;
}

/// The same flat cube as a PLY of 24 vertices (4 per side, each with its side's normal).
std::string flat_cube_ply() {
  std::ostringstream s;
  s << "ply\nformat ascii 1.0\nelement vertex 24\nproperty float x\nproperty float y\n"
       "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
       "element face 6\nproperty list uchar int vertex_indices\nend_header\n";
  for (const Side& f : kSide)
    for (const int c : f.corner)
      s << kCorner[c][0] << ' ' << kCorner[c][1] << ' ' << kCorner[c][2] << ' ' << f.normal[0]
        << ' ' << f.normal[1] << ' ' << f.normal[2] << '\n';
  for (int i = 0; i < 6; ++i)
    s << "4 " << 4 * i << ' ' << 4 * i + 1 << ' ' << 4 * i + 2 << ' ' << 4 * i + 3 << '\n';
  return s.str();
}

/// And as a .glb: one primitive of 24 vertices, two triangles per side.
std::string flat_cube_glb() {
  test::GltfPrimitive p;
  for (const Side& f : kSide) {
    const auto base = static_cast<std::uint32_t>(p.positions.size());
    for (const int c : f.corner) {
      p.positions.push_back(kCorner[c]);
      p.normals.push_back(f.normal);
    }
    for (const std::uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) p.indices.push_back(base + k);
  }
  test::GltfScene scene;
  scene.primitives.push_back(p);
  return test::glb_bytes(test::gltf_parts(scene));
}

/// A .glb's keyframes: per frame its positions and normals (base plus the frame's target).
struct Keyframes {
  std::vector<test::Floats> x, n;
  std::vector<std::uint32_t> indices;
};

Keyframes keyframes(const std::string& glb) {
  const tinygltf::Model m = test::load_glb(glb);
  Keyframes k;
  EXPECT_EQ(m.meshes.size(), 1u);
  EXPECT_EQ(m.meshes.at(0).primitives.size(), 1u);
  const tinygltf::Primitive& p = m.meshes.at(0).primitives.at(0);
  k.indices = test::read_indices(m, p.indices);
  k.x.push_back(test::read_positions(m, p.attributes.at("POSITION")));
  k.n.push_back(test::read_floats(m, p.attributes.at("NORMAL")));
  for (const auto& t : p.targets) {
    k.x.push_back(k.x[0] + test::read_floats(m, t.at("POSITION")));
    k.n.push_back(k.n[0] + test::read_floats(m, t.at("NORMAL")));
  }
  return k;
}

/// The side of the cube a triangle lies on at rest: the axis and value its corners share.
std::pair<int, float> side_of(const test::Floats& x0, const std::uint32_t* tri) {
  for (int a = 0; a < 3; ++a)
    if (x0(tri[0], a) == x0(tri[1], a) && x0(tri[1], a) == x0(tri[2], a)) return {a, x0(tri[0], a)};
  ADD_FAILURE() << "a triangle on no side of the cube";
  return {-1, 0.0f};
}

/// Per side (side_of), its area-weighted normal in frame k: the normalized sum of its
/// triangles' cross products (the side's vector area, as an OBJ's Newell normal).
std::map<std::pair<int, float>, Eigen::Vector3d> side_normals(const Keyframes& kf, std::size_t k) {
  std::map<std::pair<int, float>, Eigen::Vector3d> sum;
  for (std::size_t t = 0; t + 2 < kf.indices.size(); t += 3) {
    const std::uint32_t* tri = &kf.indices[t];
    const Eigen::Vector3d a = kf.x[k].row(tri[0]).cast<double>().transpose();
    const Eigen::Vector3d b = kf.x[k].row(tri[1]).cast<double>().transpose();
    const Eigen::Vector3d c = kf.x[k].row(tri[2]).cast<double>().transpose();
    auto [it, added] = sum.emplace(side_of(kf.x[0], tri), Eigen::Vector3d::Zero());
    it->second += (b - a).cross(c - a);
  }
  for (auto& [side, n] : sum) n.normalize();
  return sum;
}

/// Runs the CLI on `input` with a few kept frames and returns the .glb's keyframes.
Keyframes run_to_glb(const test::ScratchDir& dir, const std::string& input,
                     const std::string& output) {
  const auto r = test::run_cli({"run", input, "-o", dir.file(output), "-n", "6", "--export-every",
                                "2", "--gltf", dir.file("cube.glb"), "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return keyframes(dir.file("cube.glb"));
}

/// Per glTF vertex, the normalized sum of the cross products of the triangles that use it, in
/// frame k: a file's triangles are its polygons (a glTF input's).
std::vector<Eigen::Vector3d> triangle_normals(const Keyframes& kf, std::size_t k) {
  std::vector<Eigen::Vector3d> sum(static_cast<std::size_t>(kf.x[k].rows()),
                                   Eigen::Vector3d::Zero());
  for (std::size_t t = 0; t + 2 < kf.indices.size(); t += 3) {
    const std::uint32_t* tri = &kf.indices[t];
    const Eigen::Vector3d a = kf.x[k].row(tri[0]).cast<double>().transpose();
    const Eigen::Vector3d b = kf.x[k].row(tri[1]).cast<double>().transpose();
    const Eigen::Vector3d c = kf.x[k].row(tri[2]).cast<double>().transpose();
    for (int q = 0; q < 3; ++q) sum[tri[q]] += (b - a).cross(c - a);
  }
  for (Eigen::Vector3d& n : sum) n.normalize();
  return sum;
}

/// Every frame of a flat-shaded cube's .glb: 24 vertices, each triangle's corners with its side's
/// own normal (to float rounding of the positions and normals), and the shell moved. `quads`:
/// the file's sides are quads, so a corner's normal is its quad's; else the file's triangles
/// are its polygons, and a corner's normal is that of its side's triangles at its vertex.
void expect_flat_sides(const Keyframes& kf, bool quads) {
  ASSERT_EQ(kf.x.size(), 4u);  // frames 0, 2, 4, 6
  EXPECT_EQ(kf.x[0].rows(), 24);
  ASSERT_EQ(kf.indices.size(), 36u);
  for (std::size_t k = 0; k < kf.x.size(); ++k) {
    const auto normal = side_normals(kf, k);
    const auto per_vertex = triangle_normals(kf, k);
    EXPECT_EQ(normal.size(), 6u);
    for (std::size_t t = 0; t < kf.indices.size(); t += 3) {
      const Eigen::Vector3d side = normal.at(side_of(kf.x[0], &kf.indices[t]));
      for (std::size_t c = t; c < t + 3; ++c) {
        const Eigen::Vector3d want = quads ? side : per_vertex[kf.indices[c]];
        const Eigen::Vector3d got = kf.n[k].row(kf.indices[c]).cast<double>().transpose();
        EXPECT_LT((got - want).norm(), 1e-5)
            << "frame " << k << ", triangle " << t / 3 << ": corner normal (" << got.transpose()
            << "), its side's (" << want.transpose() << ")";
        // The side's normal, whatever the polygons: within the side's bend (the frames bend a
        // side by far less than the 90 degrees between two sides).
        EXPECT_GT(got.dot(side), 0.99);
      }
    }
  }
  EXPECT_GT((kf.x.back() - kf.x[0]).cwiseAbs().maxCoeff(), 1e-3) << "the cube did not move";
}

/// Per face of an OBJ result (quads), its corners (0-based) and the normals their `vn` name.
std::vector<std::pair<std::array<int, 4>, std::array<Eigen::Vector3d, 4>>> obj_quads(
    const std::string& path) {
  std::ifstream in(path);
  std::vector<Eigen::Vector3d> vn;
  std::vector<std::pair<std::array<int, 4>, std::array<Eigen::Vector3d, 4>>> faces;
  for (std::string line; std::getline(in, line);) {
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "vn") {
      Eigen::Vector3d n;
      ls >> n[0] >> n[1] >> n[2];
      vn.push_back(n);
    } else if (key == "f") {
      faces.emplace_back();
      for (std::size_t k = 0; k < 4; ++k) {
        std::string corner;
        ls >> corner;
        faces.back().first[k] = std::stoi(corner) - 1;
        const int normal = std::stoi(corner.substr(corner.rfind('/') + 1)) - 1;
        EXPECT_TRUE(normal >= 0 && static_cast<std::size_t>(normal) < vn.size()) << line;
        if (normal >= 0 && static_cast<std::size_t>(normal) < vn.size())
          faces.back().second[k] = vn[static_cast<std::size_t>(normal)];
      }
    }
  }
  return faces;
}

/// A flat-shaded OBJ cube run to a .glb keeps its flat sides, and the OBJ result's normals are
/// the last frame's: each side's corners name the normal the .glb gives that side's corners
/// (the writers agree).
void expect_obj_flat_cube(const std::string& obj, const char* name) {
  test::ScratchDir dir(name);
  std::ofstream(dir.file("cube.obj")) << obj;
  const Keyframes kf = run_to_glb(dir, dir.file("cube.obj"), "out.obj");
  expect_flat_sides(kf, true);
  const auto faces = obj_quads(dir.file("out.obj"));
  ASSERT_EQ(faces.size(), 6u);
  const auto last = side_normals(kf, kf.x.size() - 1);
  for (const auto& [v, normals] : faces) {
    // The side: the axis on which the polygon's corners share their rest coordinate.
    int axis = -1;
    for (int a = 0; a < 3; ++a)
      if (kCorner[v[0]][a] == kCorner[v[1]][a] && kCorner[v[1]][a] == kCorner[v[2]][a]) axis = a;
    ASSERT_GE(axis, 0);
    for (const Eigen::Vector3d& n : normals)
      EXPECT_LT((n - last.at({axis, kCorner[v[0]][axis]})).norm(), 1e-5);
  }
}

TEST(GltfHardEdges, AnObjCubeWithPerFaceNormalsKeepsItsFlatSidesInEveryFrame) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  expect_obj_flat_cube(flat_cube_obj(), "hard_obj");
  // The same values, one `vn` line per corner: the three sides at a corner still differ.
  expect_obj_flat_cube(flat_cube_obj(true), "hard_obj_corner");
}

TEST(GltfHardEdges, APlyAndAGlbCubeSplitPerSideKeepTheirFlatSides) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  test::ScratchDir dir("hard_split");
  // 24 vertices, 4 per side, each side's with its own normal: welded into 8 for the simulation.
  std::ofstream(dir.file("cube.ply"), std::ios::binary) << flat_cube_ply();
  expect_flat_sides(run_to_glb(dir, dir.file("cube.ply"), "out.ply"), true);
  std::ofstream(dir.file("cube_in.glb"), std::ios::binary) << flat_cube_glb();
  expect_flat_sides(run_to_glb(dir, dir.file("cube_in.glb"), "out.glb"), false);
}

TEST(GltfHardEdges, SmoothNormalsOrNoneAreNotSplit) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  // One normal per position: the .glb is the one of the cube without normals, byte for byte (8
  // vertices, each with the area-weighted normal of all its triangles).
  test::ScratchDir smooth("hard_smooth"), plain("hard_plain");
  std::ofstream(smooth.file("cube.obj")) << smooth_cube_obj(true);
  std::ofstream(plain.file("cube.obj")) << smooth_cube_obj(false);
  const Keyframes kf = run_to_glb(smooth, smooth.file("cube.obj"), "out.obj");
  run_to_glb(plain, plain.file("cube.obj"), "out.obj");
  EXPECT_EQ(kf.x[0].rows(), 8);
  EXPECT_EQ(test::read_bytes(smooth.file("cube.glb")), test::read_bytes(plain.file("cube.glb")));
}

TEST(GltfHardEdges, SmoothNormalsInOneLinePerCornerAreSmooth) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  // What shades corners together is the value, not the line: one `vn` per face corner, each
  // with its position's smooth value, gives the .glb and the normals of one line per position.
  test::ScratchDir per_vertex("smooth_vertex"), per_corner("smooth_corner");
  std::ofstream(per_vertex.file("cube.obj")) << smooth_cube_obj(true);
  std::ofstream(per_corner.file("cube.obj")) << smooth_cube_obj(true, true);
  run_to_glb(per_vertex, per_vertex.file("cube.obj"), "out.obj");
  const Keyframes kf = run_to_glb(per_corner, per_corner.file("cube.obj"), "out.obj");
  EXPECT_EQ(kf.x[0].rows(), 8);  // not split
  EXPECT_EQ(test::read_bytes(per_corner.file("cube.glb")),
            test::read_bytes(per_vertex.file("cube.glb")));
  // In the OBJ result every corner at one position has that position's one normal.
  const auto want = obj_quads(per_vertex.file("out.obj"));
  const auto got = obj_quads(per_corner.file("out.obj"));
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t f = 0; f < got.size(); ++f)
    for (std::size_t k = 0; k < 4; ++k) {
      ASSERT_EQ(got[f].first[k], want[f].first[k]);
      EXPECT_LT((got[f].second[k] - want[f].second[k]).norm(), 1e-12)
          << "face " << f << ", vertex " << got[f].first[k];
    }
}

/// The flat cube's animation for write_gltf_animation: 8 vertices, 12 triangles (two per
/// side, face_polygon its side), three made-up frames; `group(side, corner)` gives face_normal.
template <class Group>
GltfAnimation cube_animation(Group group) {
  GltfAnimation a;
  a.faces.resize(12, 3);
  a.face_normal.resize(12, 3);
  for (int s = 0; s < 6; ++s) {
    const auto& c = kSide[static_cast<std::size_t>(s)].corner;
    a.faces.row(2 * s) << c[0], c[1], c[2];
    a.faces.row(2 * s + 1) << c[0], c[2], c[3];
    for (int t = 0; t < 2; ++t) {
      a.face_polygon.push_back(s);  // the side is one polygon
      for (int k = 0; k < 3; ++k) a.face_normal(2 * s + t, k) = group(s, a.faces(2 * s + t, k));
    }
  }
  Positions x0(8, 3);
  for (int i = 0; i < 8; ++i)
    x0.row(i) << kCorner[static_cast<std::size_t>(i)][0], kCorner[static_cast<std::size_t>(i)][1],
        kCorner[static_cast<std::size_t>(i)][2];
  for (int f = 0; f <= 20; f += 10) {
    a.frame_numbers.push_back(f);
    a.frames.push_back(test::fake_frame(x0, f, 20));
  }
  return a;
}

TEST(GltfHardEdges, NormalGroupsSplitOnlyVerticesWhoseCornersDiffer) {
  test::ScratchDir dir("hard_lib");
  // One group per side: every corner of the cube is on 3 sides.
  write_gltf_animation(dir.file("flat.glb"), cube_animation([](int side, int) { return side; }));
  const Keyframes flat = keyframes(dir.file("flat.glb"));
  EXPECT_EQ(flat.x[0].rows(), 24);
  // One group per vertex (smooth normals), or none at all: the file without normal groups.
  write_gltf_animation(dir.file("smooth.glb"), cube_animation([](int, int v) { return v; }));
  write_gltf_animation(dir.file("none.glb"), cube_animation([](int, int) { return -1; }));
  GltfAnimation plain = cube_animation([](int, int) { return 0; });
  plain.face_normal.resize(0, 3);
  plain.face_polygon.clear();
  write_gltf_animation(dir.file("plain.glb"), plain);
  EXPECT_EQ(test::read_bytes(dir.file("smooth.glb")), test::read_bytes(dir.file("plain.glb")));
  EXPECT_EQ(test::read_bytes(dir.file("none.glb")), test::read_bytes(dir.file("plain.glb")));
  // The top's corners apart from the rest, whose corners have no normal (a lid): its 4 vertices
  // split in two, the bottom's not; the lid's corners have its normal, every other corner the
  // smooth normal of all its vertex's faces, as without groups.
  write_gltf_animation(dir.file("lid.glb"),
                       cube_animation([](int side, int) { return side == 1 ? 1 : -1; }));
  const Keyframes lid = keyframes(dir.file("lid.glb"));
  EXPECT_EQ(lid.x[0].rows(), 12);
  const Keyframes none = keyframes(dir.file("none.glb"));
  for (std::size_t k = 0; k < lid.x.size(); ++k) {
    const auto normal = side_normals(lid, k);
    for (std::size_t t = 0; t < lid.indices.size(); t += 3) {
      const auto side = side_of(lid.x[0], &lid.indices[t]);
      for (std::size_t c = t; c < t + 3; ++c) {
        const Eigen::Vector3d got = lid.n[k].row(lid.indices[c]).cast<double>().transpose();
        const bool top = side == std::make_pair(2, 1.0f);
        // The same vertex's normal in the file without groups (its index there: its own).
        const Eigen::Vector3d all = none.n[k].row(none.indices[c]).cast<double>().transpose();
        if (top)
          EXPECT_LT((got - normal.at(side)).norm(), 1e-5) << "frame " << k;
        else
          EXPECT_EQ(got, all) << "frame " << k;
      }
    }
  }
}

TEST(GltfHardEdges, NormalGroupsOfAnotherSizeOrBelowMinusOneAreRefused) {
  GltfAnimation a = cube_animation([](int side, int) { return side; });
  a.face_normal.conservativeResize(11, 3);
  EXPECT_THROW(write_gltf_animation("/nonexistent/x.glb", a), std::invalid_argument);
  a = cube_animation([](int side, int) { return side - 2; });
  EXPECT_THROW(write_gltf_animation("/nonexistent/x.glb", a), std::invalid_argument);
  a = cube_animation([](int side, int) { return side; });
  a.face_polygon[3] = 12;  // 12 faces: polygons are numbered below that
  EXPECT_THROW(write_gltf_animation("/nonexistent/x.glb", a), std::invalid_argument);
  a.face_polygon[3] = 1;
  a.face_polygon.pop_back();
  EXPECT_THROW(write_gltf_animation("/nonexistent/x.glb", a), std::invalid_argument);
}

}  // namespace
}  // namespace shellcontract
