// The cost of splitting one large polygon is bounded (review7 F9: a 266 KB OBJ of one comb-shaped
// face of 16,000 corners took 63 s before any message): a polygon of more than MAX_SPLIT_CORNERS
// corners is refused naming its face and line, and the rules try a fan without making it, so the
// polygons that are split cost far less. They are split as before: the splits below are compared
// with the previous code, kept here as the reference.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "mesh/polygon_split.hpp"
#include "mesh/soup_geometry.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace {

using shellcontract::InputError;
using shellcontract::Point3;
using shellcontract::Vec3;
using shellcontract::soup::MAX_SPLIT_CORNERS;
using shellcontract::soup::Polygon;
using shellcontract::soup::split_polygon;
using shellcontract::soup::SplitRule;
using shellcontract::soup::to_vec;
using shellcontract::soup::ZERO_AREA_RELATIVE;

const double PI = std::acos(-1.0);

// ---- The previous split_polygon (src/mesh/polygon_split.cpp before), its code unchanged.
namespace before {

Vec3 newell_normal(const Polygon& p, const std::vector<Point3>& pts) {
  const std::size_t n = p.size();
  Vec3 normal = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i)
    normal += to_vec(pts[p[i]]).cross(to_vec(pts[p[(i + 1) % n]]));
  return normal;
}
Vec3 area_vector(const Polygon& t, const std::vector<Point3>& pts) {
  const Vec3 a = to_vec(pts[t[0]]);
  return (to_vec(pts[t[1]]) - a).cross(to_vec(pts[t[2]]) - a);
}
std::vector<Polygon> fan(const Polygon& p, std::size_t k) {
  const std::size_t n = p.size();
  std::vector<Polygon> tris;
  for (std::size_t j = 1; j + 1 < n; ++j)
    tris.push_back({p[k], p[(k + j) % n], p[(k + j + 1) % n]});
  return tris;
}
double zero_area_threshold(const Polygon& p, const std::vector<Point3>& pts) {
  double sum = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    sum += (to_vec(pts[p[i]]) - to_vec(pts[p[(i + 1) % p.size()]])).norm();
  const double mean = sum / static_cast<double>(p.size());
  return ZERO_AREA_RELATIVE * mean * mean;
}
std::vector<Polygon> least_folded_diagonal(const Polygon& p, const std::vector<Point3>& pts) {
  const double zero = zero_area_threshold(p, pts);
  double best = -std::numeric_limits<double>::infinity();
  std::size_t best_k = 0;
  for (std::size_t k = 0; k < 2; ++k) {
    const std::vector<Polygon> t = fan(p, k);
    const Vec3 a = area_vector(t[0], pts), b = area_vector(t[1], pts);
    const double score =
        (a.norm() < zero || b.norm() < zero) ? -2.0 : a.normalized().dot(b.normalized());
    if (score > best) {
      best = score;
      best_k = k;
    }
  }
  return fan(p, best_k);
}
std::vector<Polygon> ear_clip(const Polygon& p, const std::vector<Point3>& pts,
                              const Vec3& normal) {
  const Vec3 w = normal.normalized();
  const Vec3 u = (std::abs(w.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(w).normalized();
  const Vec3 v = w.cross(u);
  struct P2 {
    double x, y;
  };
  std::vector<P2> q;
  for (const std::size_t i : p) q.push_back({to_vec(pts[i]).dot(u), to_vec(pts[i]).dot(v)});
  const auto cross = [&q](std::size_t a, std::size_t b, std::size_t c) {
    return (q[b].x - q[a].x) * (q[c].y - q[a].y) - (q[b].y - q[a].y) * (q[c].x - q[a].x);
  };
  std::vector<std::size_t> left(p.size());
  for (std::size_t i = 0; i < left.size(); ++i) left[i] = i;
  std::vector<Polygon> tris;
  std::size_t i = 0, tried = 0;
  while (left.size() > 3) {
    const std::size_t m = left.size();
    if (tried == m) return {};
    i %= m;
    const std::size_t a = left[(i + m - 1) % m], b = left[i], c = left[(i + 1) % m];
    bool ear = cross(a, b, c) > 0.0;
    for (std::size_t j = 0; j < m && ear; ++j) {
      const std::size_t o = left[j];
      if (o == a || o == b || o == c) continue;
      ear = cross(a, b, o) < 0.0 || cross(b, c, o) < 0.0 || cross(c, a, o) < 0.0;
    }
    if (!ear) {
      ++i;
      ++tried;
      continue;
    }
    tris.push_back({p[a], p[b], p[c]});
    left.erase(left.begin() + static_cast<std::ptrdiff_t>(i));
    i = (i + m - 2) % (m - 1);
    tried = 0;
  }
  if (!(cross(left[0], left[1], left[2]) > 0.0)) return {};
  tris.push_back({p[left[0]], p[left[1]], p[left[2]]});
  return tris;
}
std::vector<Polygon> best_fan(const Polygon& p, const std::vector<Point3>& pts,
                              const Vec3& normal) {
  const double zero = zero_area_threshold(p, pts);
  const Vec3 w = normal.normalized();
  double best = -std::numeric_limits<double>::infinity();
  std::vector<Polygon> chosen;
  for (std::size_t k = 0; k < p.size(); ++k) {
    std::vector<Polygon> t = fan(p, k);
    double worst = 1.0;
    for (const Polygon& tri : t) {
      const Vec3 a = area_vector(tri, pts);
      worst = a.norm() < zero ? -std::numeric_limits<double>::infinity()
                              : std::min(worst, a.normalized().dot(w));
    }
    if (worst > best) {
      best = worst;
      chosen = std::move(t);
    }
  }
  return chosen;
}
std::vector<Polygon> split_polygon(const Polygon& p, const std::vector<Point3>& pts,
                                   SplitRule* rule) {
  const auto by = [rule](SplitRule r, std::vector<Polygon> tris) {
    if (rule != nullptr && !tris.empty()) *rule = r;
    return tris;
  };
  const Vec3 normal = newell_normal(p, pts);
  if (normal.squaredNorm() == 0.0) return by(SplitRule::flat, fan(p, 0));
  for (std::size_t k = 0; k < p.size(); ++k) {
    std::vector<Polygon> tris = fan(p, k);
    bool ok = true;
    for (const Polygon& t : tris) ok = ok && area_vector(t, pts).dot(normal) > 0.0;
    if (ok) return by(SplitRule::fan, std::move(tris));
  }
  if (p.size() == 4) return by(SplitRule::diagonal, least_folded_diagonal(p, pts));
  std::vector<Polygon> tris = ear_clip(p, pts, normal);
  if (!tris.empty()) return by(SplitRule::ear_clip, std::move(tris));
  return by(SplitRule::best_fan, best_fan(p, pts, normal));
}

}  // namespace before

// Random polygons of every kind the rules meet: convex and star-shaped ones (a fan), spiky
// simple ones (ear clipping), bent ones off their plane, self-crossing ones (the best fan or a
// refusal) and ones with repeated positions (zero-area triangles); every rule is reached.
TEST(SplitPolygonBounds, EveryPolygonIsSplitAsBefore) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::size_t by_rule[shellcontract::soup::SPLIT_RULES] = {}, refused = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const std::size_t n = 4 + static_cast<std::size_t>(u(rng) * 40);
    const int kind = trial % 5;
    std::vector<Point3> pts;
    for (std::size_t i = 0; i < n; ++i) {
      const double a = 2.0 * PI * (static_cast<double>(i) + (kind == 0 ? 0.0 : 0.4 * u(rng))) / n;
      const double r = kind == 0 ? 1.0 : kind == 1 ? 0.8 + 0.2 * u(rng) : 0.1 + u(rng);
      const double z = kind >= 3 ? 0.6 * (u(rng) - 0.5) : 0.0;
      pts.emplace_back(r * std::cos(a), r * std::sin(a), z);
    }
    if (kind == 4) std::shuffle(pts.begin() + 1, pts.end(), rng);  // crossing itself
    if (trial % 7 == 0) pts[2] = pts[1];                           // a repeated position
    Polygon p(n);
    for (std::size_t i = 0; i < n; ++i) p[i] = i;
    SplitRule was = SplitRule::fan, is = SplitRule::fan;
    const std::vector<Polygon> expected = before::split_polygon(p, pts, &was);
    ASSERT_EQ(split_polygon(p, pts, &is), expected) << "trial " << trial;
    if (expected.empty()) {
      ++refused;
      continue;
    }
    ASSERT_EQ(is, was) << "trial " << trial;
    ++by_rule[static_cast<std::size_t>(was)];
  }
  EXPECT_GT(by_rule[static_cast<std::size_t>(SplitRule::fan)], 0u);
  EXPECT_GT(by_rule[static_cast<std::size_t>(SplitRule::diagonal)], 0u);
  EXPECT_GT(by_rule[static_cast<std::size_t>(SplitRule::ear_clip)], 0u);
  EXPECT_GT(by_rule[static_cast<std::size_t>(SplitRule::best_fan)], 0u);
  EXPECT_GT(refused, 0u);
}

/// An OBJ of one convex planar polygon of n corners after a comment line: its face is on line
/// n + 2.
std::string polygon_obj(const std::string& name, std::size_t n) {
  const std::string path =
      (std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + name)).string();
  std::ofstream f(path);
  f << "# one polygon\n";
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2.0 * PI * static_cast<double>(i) / static_cast<double>(n);
    f << "v " << std::cos(a) << ' ' << std::sin(a) << " 0\n";
  }
  f << 'f';
  for (std::size_t i = 1; i <= n; ++i) f << ' ' << i;
  f << '\n';
  return path;
}

std::string refusal(const std::string& path) {
  try {
    shellcontract::read_input_mesh(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "read";
}

// Above the bound: refused before any split, naming the face, its line and both counts. At the
// bound: split, and then refused for what one polygon is, an open surface.
TEST(SplitPolygonBounds, APolygonAboveTheBoundIsRefusedNamingItsLine) {
  const std::size_t n = MAX_SPLIT_CORNERS + 1;
  const std::string big = polygon_obj("shellcontract_big_polygon.obj", n);
  const std::string m = refusal(big);
  EXPECT_EQ(m.rfind(big + ": polygon too large: face 0 (line " + std::to_string(n + 2) + ") has " +
                        std::to_string(n) + " vertices, more than the " +
                        std::to_string(MAX_SPLIT_CORNERS),
                    0),
            0u)
      << m;
  EXPECT_NE(m.find("triangulate it in your modelling tool"), std::string::npos) << m;
  std::filesystem::remove(big);

  const std::string at = polygon_obj("shellcontract_bound_polygon.obj", MAX_SPLIT_CORNERS);
  const std::string ok = refusal(at);
  EXPECT_NE(ok.find("open boundary"), std::string::npos) << ok;
  std::filesystem::remove(at);
}

// The bound is per polygon, and a file may hold many (complexity F5: copies of a star polygon of
// 10000 corners were each split before they were refused as duplicate faces): the
// squares of the corners of the polygons above SMALL_SPLIT_CORNERS add up to at most
// MAX_SPLIT_WORK. One polygon more is refused before any is split, naming the count and the
// largest; the old code split all eleven and refused a duplicate face. At the bound the polygons
// are split and refused for what they are.
TEST(SplitPolygonBounds, PolygonsPastTheTotalBoundAreRefusedBeforeAnySplit) {
  using shellcontract::soup::MAX_SPLIT_WORK;
  using shellcontract::soup::SMALL_SPLIT_CORNERS;
  const std::size_t n = MAX_SPLIT_CORNERS;
  std::vector<Point3> points;
  Polygon ring;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2.0 * PI * static_cast<double>(i) / static_cast<double>(n);
    points.emplace_back(std::cos(a), std::sin(a), 0.0);
    ring.push_back(i);
  }
  ASSERT_EQ(MAX_SPLIT_WORK / (n * n), 10u);
  std::vector<Polygon> polygons(10, ring);
  polygons.push_back(
      {0, n / 3, 2 * n / 3});  // a triangle and a polygon of few corners do not count
  polygons.push_back(Polygon(ring.begin(), ring.begin() + SMALL_SPLIT_CORNERS));
  const auto message = [&](const std::vector<Polygon>& faces) -> std::string {
    try {
      shellcontract::check_input_soup("soup", points, faces);
    } catch (const InputError& e) {
      return e.what();
    }
    return "read";
  };
  const std::string at = message(polygons);
  EXPECT_EQ(at.find("polygons too large"), std::string::npos) << at;
  EXPECT_NE(at.find("duplicate face"), std::string::npos) << at;
  polygons.push_back(Polygon(ring.rbegin(), ring.rend()));  // an eleventh of MAX_SPLIT_CORNERS
  const std::string past = message(polygons);
  EXPECT_EQ(past,
            "soup: polygons too large in all: 11 polygons have more than 100 vertices (the "
            "largest: face 0, "
            "10000 vertices); splitting one takes time of the square of its vertices, and theirs "
            "add up to 1100000000, more "
            "than the 1000000000 (ten polygons of 10000 vertices) that this reader splits into "
            "triangles; "
            "triangulate them in your modelling tool (Blender: Face > Triangulate Faces) before "
            "using the file");
}

}  // namespace
