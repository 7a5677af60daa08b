// OBJ normals that exporters share by value: Blender's OBJ exporter writes each distinct normal
// once, so on a smooth-shaded subdivided cube every vertex inside one side uses the same `vn`
// line, and on a flat-shaded one every polygon of a side does. After a run those vertices and
// polygons no longer face one way; each vertex's corners must get the normal of their own
// polygons, which means more `vn` lines than were read. The expected normals are computed
// here from the polygons' vector areas, and the written file is read back corner by corner.
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

/// A cube of n x n quads per side, normals written once per distinct value (as Blender does):
/// smooth, each vertex's normal is the sign of its coordinates on the cube's faces (26 values);
/// flat (`s 0`), one per side (6). Relative: corners as negative indices.
struct SharedNormalCube {
  std::string text;
  Positions x;
  std::vector<std::vector<std::size_t>> polygons;  ///< vertex indices, outward
};

SharedNormalCube shared_normal_cube(int n, bool flat, bool relative) {
  SharedNormalCube c;
  std::map<std::array<int, 3>, std::size_t> vertex_of;  // grid point (2i - n per axis) -> index
  std::vector<std::array<int, 3>> points;
  std::map<std::array<int, 3>, std::size_t> normal_of;  // sign triple -> vn index
  std::vector<std::array<int, 3>> normals;
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> faces;  // (v, vn) corners
  for (int a = 0; a < 3; ++a)
    for (const int s : {-1, 1}) {
      const int b = (a + 1) % 3, cc = (a + 2) % 3;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          std::vector<std::array<int, 2>> uv = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
          if (s < 0) std::swap(uv[1], uv[3]);  // e_b x e_c = e_a: reversed on the - side
          std::vector<std::pair<std::size_t, std::size_t>> face;
          for (const auto& q : uv) {
            std::array<int, 3> p{};
            p[static_cast<std::size_t>(a)] = s * n;
            p[static_cast<std::size_t>(b)] = 2 * q[0] - n;
            p[static_cast<std::size_t>(cc)] = 2 * q[1] - n;
            const auto v = vertex_of.emplace(p, points.size());
            if (v.second) points.push_back(p);
            std::array<int, 3> sign{};
            if (flat) {
              sign[static_cast<std::size_t>(a)] = s;
            } else {
              for (std::size_t k = 0; k < 3; ++k) sign[k] = p[k] == n ? 1 : p[k] == -n ? -1 : 0;
            }
            const auto vn = normal_of.emplace(sign, normals.size());
            if (vn.second) normals.push_back(sign);
            face.emplace_back(v.first->second, vn.first->second);
          }
          faces.push_back(face);
        }
    }
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
  o << (flat ? "s 0\n" : "s 1\n");
  const long long nv = static_cast<long long>(points.size()), nn = static_cast<long long>(normals.size());
  for (const auto& f : faces) {
    o << 'f';
    std::vector<std::size_t> poly;
    for (const auto& [v, vn] : f) {
      const long long vi = static_cast<long long>(v), ni = static_cast<long long>(vn);
      if (relative)
        o << ' ' << vi - nv << "//" << ni - nn;
      else
        o << ' ' << vi + 1 << "//" << ni + 1;
      poly.push_back(v);
    }
    o << '\n';
    c.polygons.push_back(poly);
  }
  c.text = o.str();
  return c;
}

/// The positions moved by a random-looking field: no two polygons of a side face one way.
Positions wrinkled(const Positions& x) {
  Positions y = x;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> d(-0.3, 0.3);
  for (Eigen::Index i = 0; i < y.rows(); ++i)
    for (int k = 0; k < 3; ++k) y(i, k) += d(rng);
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

void expect_smooth_normals(bool relative) {
  const SharedNormalCube c = shared_normal_cube(3, false, relative);
  const Positions y = wrinkled(c.x);
  std::vector<Vec3> expect(static_cast<std::size_t>(y.rows()), Vec3::Zero());
  for (const auto& p : c.polygons)
    for (const std::size_t v : p) expect[v] += vector_area(y, p);
  const std::string out = parse_obj_document("cube.obj", c.text)->text(y);
  // The tool reads back what it wrote (every normal index defined before its face).
  EXPECT_NO_THROW(parse_obj_document("out.obj", out));
  const auto corners = corner_normals(out);
  ASSERT_EQ(corners.size(), c.polygons.size());
  for (std::size_t p = 0; p < corners.size(); ++p)
    for (const auto& [v, n] : corners[p])
      EXPECT_NEAR((n - expect[v].normalized()).norm(), 0.0, 1e-13) << "polygon " << p << ", vertex " << v;
}

TEST(ObjSharedNormals, ASmoothNormalSharedByManyVerticesBecomesEachVertexsNormal) {
  expect_smooth_normals(false);
}

TEST(ObjSharedNormals, RelativeIndicesStillNameEachCornersNormal) { expect_smooth_normals(true); }

TEST(ObjSharedNormals, AFlatSidesNormalBecomesOneNormalPerVertexOfTheSide) {
  // One `vn` per side: at a vertex, the polygons of one side share it, so they are smoothed
  // together there (the file's coplanar polygons do not say they were meant to be faceted), and
  // the polygons of the other sides at that vertex are not (the box's hard edges stay).
  const int n = 3;
  const SharedNormalCube c = shared_normal_cube(n, true, false);
  const Positions y = wrinkled(c.x);
  const std::size_t per_side = static_cast<std::size_t>(n * n);  // polygons are side by side
  const std::string out = parse_obj_document("cube.obj", c.text)->text(y);
  EXPECT_NO_THROW(parse_obj_document("out.obj", out));
  const auto corners = corner_normals(out);
  ASSERT_EQ(corners.size(), c.polygons.size());
  for (std::size_t p = 0; p < corners.size(); ++p)
    for (const auto& [v, n_out] : corners[p]) {
      Vec3 expect = Vec3::Zero();
      for (std::size_t q = 0; q < c.polygons.size(); ++q)
        if (q / per_side == p / per_side)
          for (const std::size_t w : c.polygons[q]) expect += w == v ? vector_area(y, c.polygons[q]) : Vec3::Zero();
      EXPECT_NEAR((n_out - expect.normalized()).norm(), 0.0, 1e-13) << "polygon " << p << ", vertex " << v;
    }
}

}  // namespace
}  // namespace shellcontract
