// OBJ normals that exporters share by value: Blender's OBJ exporter writes each distinct normal
// once, so on a smooth-shaded subdivided cube every vertex inside one side uses the same `vn`
// line, and on a flat-shaded one every polygon of a side does. After a run those vertices and
// polygons no longer face one way; each vertex's corners must get the normal of their own
// polygons, which means more `vn` lines than were read. Other exporters repeat a value in many
// lines (one per face corner, one per vertex copy at a seam): what shades corners together is
// the value, not the line. The expected normals are computed here from the polygons' vector
// areas, and the written file is read back corner by corner.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

/// How a cube's file lays its normal values out in `vn` lines.
enum class Lines {
  kPerValue,   ///< each distinct value once (Blender's exporter)
  kPerCorner,  ///< one line per face corner, in face order
  kPerVertex,  ///< one line per `v` line, corners `f a//a` (exporters of split vertex buffers)
};

struct CubeLayout {
  bool flat = false;      ///< one value per side (hard edges); else one per position (smooth)
  bool relative = false;  ///< corners as negative indices
  Lines lines = Lines::kPerValue;
  bool split_sides = false;  ///< each side its own copies of its edge vertices (a seam per edge)
};

/// A cube of n x n quads per side: smooth, each vertex's normal is the sign of its coordinates on
/// the cube's faces (26 values); flat (`s 0`), one per side (6).
struct SharedNormalCube {
  std::string text;
  Positions x;
  std::vector<std::size_t> position;               ///< per vertex: its grid point (copies share it)
  std::vector<std::vector<std::size_t>> polygons;  ///< vertex indices, outward
};

SharedNormalCube shared_normal_cube(int n, const CubeLayout& layout) {
  SharedNormalCube c;
  std::map<std::array<int, 4>, std::size_t>
      vertex_of;  // (grid point (2i - n per axis), side) -> index
  std::map<std::array<int, 3>, std::size_t> point_of;   // grid point -> position
  std::vector<std::array<int, 3>> points;               // per vertex
  std::map<std::array<int, 3>, std::size_t> normal_of;  // sign triple -> vn index (kPerValue)
  std::vector<std::array<int, 3>> normals;
  std::vector<std::vector<std::pair<std::size_t, std::array<int, 3>>>> faces;  // (v, value) corners
  for (int a = 0; a < 3; ++a)
    for (const int s : {-1, 1}) {
      const int b = (a + 1) % 3, cc = (a + 2) % 3;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          std::vector<std::array<int, 2>> uv = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
          if (s < 0) std::swap(uv[1], uv[3]);  // e_b x e_c = e_a: reversed on the - side
          std::vector<std::pair<std::size_t, std::array<int, 3>>> face;
          for (const auto& q : uv) {
            std::array<int, 3> p{};
            p[static_cast<std::size_t>(a)] = s * n;
            p[static_cast<std::size_t>(b)] = 2 * q[0] - n;
            p[static_cast<std::size_t>(cc)] = 2 * q[1] - n;
            const int side = layout.split_sides ? 2 * a + (s > 0) : 0;
            const auto v =
                vertex_of.emplace(std::array<int, 4>{p[0], p[1], p[2], side}, points.size());
            if (v.second) {
              points.push_back(p);
              c.position.push_back(point_of.emplace(p, point_of.size()).first->second);
            }
            std::array<int, 3> sign{};
            if (layout.flat) {
              sign[static_cast<std::size_t>(a)] = s;
            } else {
              for (std::size_t k = 0; k < 3; ++k) sign[k] = p[k] == n ? 1 : p[k] == -n ? -1 : 0;
            }
            face.emplace_back(v.first->second, sign);
          }
          faces.push_back(face);
        }
    }
  // The `vn` index of each corner, by the layout.
  std::vector<std::vector<std::size_t>> corner_vn;
  std::vector<std::array<int, 3>> vertex_value(points.size());
  for (const auto& f : faces)
    for (const auto& [v, sign] : f) vertex_value[v] = sign;
  for (const auto& f : faces) {
    corner_vn.emplace_back();
    for (const auto& [v, sign] : f) {
      std::size_t vn = v;
      if (layout.lines == Lines::kPerValue) {
        vn = normal_of.emplace(sign, normals.size()).first->second;
        if (vn == normals.size()) normals.push_back(sign);
      } else if (layout.lines == Lines::kPerCorner) {
        vn = normals.size();
        normals.push_back(sign);
      }
      corner_vn.back().push_back(vn);
    }
  }
  if (layout.lines == Lines::kPerVertex)
    normals = vertex_value;  // one value per copy: no hard edge
  std::ostringstream o;
  o << "o Cube\n";
  c.x.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) {
    o << "v " << points[i][0] << ' ' << points[i][1] << ' ' << points[i][2] << '\n';
    for (int k = 0; k < 3; ++k) c.x(static_cast<Eigen::Index>(i), k) = points[i][static_cast<std::size_t>(k)];
  }
  for (const auto& s : normals) {
    const Vec3 m = Vec3(s[0], s[1], s[2]).normalized();
    o << "vn " << m.x() << ' ' << m.y() << ' ' << m.z() << '\n';
  }
  o << (layout.flat ? "s 0\n" : "s 1\n");
  const long long nv = static_cast<long long>(points.size()), nn = static_cast<long long>(normals.size());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    o << 'f';
    std::vector<std::size_t> poly;
    for (std::size_t k = 0; k < faces[f].size(); ++k) {
      const long long vi = static_cast<long long>(faces[f][k].first);
      const long long ni = static_cast<long long>(corner_vn[f][k]);
      if (layout.relative)
        o << ' ' << vi - nv << "//" << ni - nn;
      else
        o << ' ' << vi + 1 << "//" << ni + 1;
      poly.push_back(faces[f][k].first);
    }
    o << '\n';
    c.polygons.push_back(poly);
  }
  c.text = o.str();
  return c;
}

/// The positions moved by a random-looking field: no two polygons of a side face one way. The
/// copies of a vertex (split_sides) move together, as the simulation moves them.
Positions wrinkled(const SharedNormalCube& c) {
  Positions y = c.x;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> d(-0.3, 0.3);
  std::map<std::size_t, Vec3> moved;
  for (Eigen::Index i = 0; i < y.rows(); ++i) {
    const auto m = moved.emplace(c.position[static_cast<std::size_t>(i)], Vec3::Zero());
    if (m.second)
      for (int k = 0; k < 3; ++k) m.first->second[k] = d(rng);
    y.row(i) += m.first->second.transpose();
  }
  return y;
}

Vec3 vector_area(const Positions& y, const std::vector<std::size_t>& p) {
  Vec3 area = Vec3::Zero();
  const Vec3 a = y.row(static_cast<Eigen::Index>(p[0])).transpose();
  for (std::size_t k = 1; k + 1 < p.size(); ++k)
    area += (y.row(static_cast<Eigen::Index>(p[k])).transpose() - a)
                .cross(y.row(static_cast<Eigen::Index>(p[k + 1])).transpose() - a);
  return area;
}

/// Per polygon of the written text, per corner: (vertex, the normal its vn index names), with
/// relative indices resolved against the lines defined before the face, as readers do.
std::vector<std::vector<std::pair<std::size_t, Vec3>>> corner_normals(const std::string& text) {
  std::vector<std::vector<std::pair<std::size_t, Vec3>>> out;
  std::vector<Vec3> vn;
  long long v_count = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::istringstream l(line);
    std::string key;
    l >> key;
    if (key == "v") {
      ++v_count;
    } else if (key == "vn") {
      double a = 0, b = 0, c = 0;
      l >> a >> b >> c;
      vn.emplace_back(a, b, c);
    } else if (key == "f") {
      std::vector<std::pair<std::size_t, Vec3>> poly;
      for (std::string t; l >> t;) {
        const std::size_t slash = t.find("//");
        const long long v = std::atoll(t.substr(0, slash).c_str());
        const long long n = std::atoll(t.substr(slash + 2).c_str());
        const long long vi = v > 0 ? v - 1 : v_count + v;
        const long long ni = n > 0 ? n - 1 : static_cast<long long>(vn.size()) + n;
        EXPECT_TRUE(ni >= 0 && ni < static_cast<long long>(vn.size())) << line;
        if (ni < 0 || ni >= static_cast<long long>(vn.size())) return out;
        poly.emplace_back(static_cast<std::size_t>(vi), vn[static_cast<std::size_t>(ni)]);
      }
      out.push_back(poly);
    }
  }
  return out;
}

/// The file's `f` lines, in order.
std::vector<std::string> face_lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("f ", 0) == 0) out.push_back(line);
  return out;
}

/// The cube written at wrinkled positions: every corner has the normalized sum of the vector
/// areas of the polygons around its position (all of them when smooth; those of its own side when
/// flat, so the box's hard edges stay), whatever lines held the values.
/// `offset` moves the result far from the origin (UTM metres): the normals must not depend on it.
void expect_normals(const CubeLayout& layout, const Vec3& offset = Vec3::Zero()) {
  const int n = 3;
  const SharedNormalCube c = shared_normal_cube(n, layout);
  const Positions y = wrinkled(c).rowwise() + offset.transpose();
  const std::size_t per_side = static_cast<std::size_t>(n * n);  // polygons are side by side
  const std::string out = parse_obj_document("cube.obj", c.text)->text(y);
  // The tool reads back what it wrote (every normal index defined before its face).
  EXPECT_NO_THROW(parse_obj_document("out.obj", out));
  const auto corners = corner_normals(out);
  ASSERT_EQ(corners.size(), c.polygons.size());
  for (std::size_t p = 0; p < corners.size(); ++p)
    for (const auto& [v, n_out] : corners[p]) {
      Vec3 expect = Vec3::Zero();
      for (std::size_t q = 0; q < c.polygons.size(); ++q)
        if (!layout.flat || q / per_side == p / per_side)
          for (const std::size_t w : c.polygons[q])
            if (c.position[w] == c.position[v]) expect += vector_area(y, c.polygons[q]);
      EXPECT_NEAR((n_out - expect.normalized()).norm(), 0.0, 1e-13)
          << "polygon " << p << ", vertex " << v;
    }
  // Lines that each served one group of corners stay one normal each: the face lines are kept.
  if (layout.lines != Lines::kPerValue) {
    EXPECT_EQ(face_lines(out), face_lines(c.text));
  }
}

TEST(ObjSharedNormals, ASmoothNormalSharedByManyVerticesBecomesEachVertexsNormal) {
  expect_normals({});
}

TEST(ObjSharedNormals, RelativeIndicesStillNameEachCornersNormal) {
  CubeLayout relative;
  relative.relative = true;
  expect_normals(relative);
}

TEST(ObjSharedNormals, AFlatSidesNormalBecomesOneNormalPerVertexOfTheSide) {
  // One `vn` per side: at a vertex, the polygons of one side share it, so they are smoothed
  // together there (the file's coplanar polygons do not say they were meant to be faceted), and
  // the polygons of the other sides at that vertex are not (the box's hard edges stay).
  CubeLayout flat;
  flat.flat = true;
  expect_normals(flat);
}

// Exporters that write one `vn` line per face corner, or one per vertex copy of a mesh split at
// its UV seams, repeat a value in many lines: the corners at one position with the same value
// are one smooth vertex (not faceted, no crease along the seams), and corners with different
// values (the flat cube's three sides at each corner) stay apart.
TEST(ObjSharedNormals, OneLinePerCornerWithOneValuePerPositionIsSmooth) {
  CubeLayout per_corner;
  per_corner.lines = Lines::kPerCorner;
  expect_normals(per_corner);
  per_corner.relative = true;
  expect_normals(per_corner);
}

TEST(ObjSharedNormals, OneLinePerCornerKeepsTheHardEdgesOfDifferentValues) {
  CubeLayout flat;
  flat.flat = true;
  flat.lines = Lines::kPerCorner;
  expect_normals(flat);
}

TEST(ObjSharedNormals, OneLinePerSeamCopyWithOneValueShowsNoSeam) {
  CubeLayout split;
  split.lines = Lines::kPerVertex;
  split.split_sides = true;
  expect_normals(split);
  split.flat = true;  // each side's copies with the side's value: the edges stay hard
  expect_normals(split);
}

TEST(ObjSharedNormals, NormalsOfAResultFarFromTheOriginAreThoseOfItsShape) {
  // At northing 5e6 a polygon's corners are of size 5e6 and its area of order 0.1: a Newell sum of
  // the corners' absolute cross products (terms of 1e13) kept nothing of the normal but rounding
  // (review numguards M1). The expected normals are taken from edge vectors, as near the origin.
  expect_normals({}, Vec3(500000.0, 5000000.0, 100.0));
  CubeLayout flat;
  flat.flat = true;
  expect_normals(flat, Vec3(500000.0, 5000000.0, 100.0));
}

}  // namespace
}  // namespace shellcontract
