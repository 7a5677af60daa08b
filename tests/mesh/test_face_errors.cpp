// FaceListError: a soup refused because of particular faces (or of a non-manifold vertex: the
// faces around it) throws the InputError subclass with their triangle indices as data, all of
// them even where the message lists only the first ten; its message is the InputError's as before.
#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include "shellcontract/face_error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/soup_arrays.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

using Arrays = test::SoupArrays;

Arrays ico(const char* name = "ico2.off") { return test::arrays_of_test_mesh(name); }

/// The FaceListError mesh_from_arrays throws for `a` (fails the test if it throws anything else).
FaceListError refusal(const Arrays& a) {
  TriangleSoupView s;
  s.vertices = a.v.data();
  s.num_vertices = a.v.size() / 3;
  s.faces64 = a.f.data();
  s.num_faces = a.f.size() / 3;
  try {
    mesh_from_arrays(s, "arrays");
  } catch (const FaceListError& e) {
    return e;
  } catch (const InputError& e) {
    ADD_FAILURE() << "a plain InputError: " << e.what();
  }
  ADD_FAILURE() << "no FaceListError";
  return FaceListError("", {});
}

TEST(FaceErrors, NonManifoldEdgeCarriesEveryFaceTheMessageShortens) {
  Arrays a = ico();
  const std::size_t nf = a.f.size() / 3, nv = a.v.size() / 3;
  const std::int64_t p = a.f[0], q = a.f[1];
  std::size_t other = nf;
  for (std::size_t g = 1; g < nf; ++g) {
    int shared = 0;
    for (int k = 0; k < 3; ++k) shared += a.f[3 * g + k] == p || a.f[3 * g + k] == q;
    if (shared == 2) other = g;
  }
  ASSERT_LT(other, nf);
  // Twelve triangles more on face 0's first edge, each with a vertex of its own inside.
  for (int k = 0; k < 12; ++k) {
    a.v.insert(a.v.end(), {0.01 * (k + 1), 0.003 * (k + 1), 0.007 * (k + 1)});
    a.f.insert(a.f.end(), {q, p, static_cast<std::int64_t>(nv + k)});
  }
  const FaceListError e = refusal(a);
  std::vector<std::size_t> expected = {0, other};
  for (std::size_t k = 0; k < 12; ++k) expected.push_back(nf + k);
  EXPECT_EQ(e.faces(), expected);
  std::string listed;
  for (std::size_t i = 0; i < 10; ++i) listed += (i ? ", " : "") + std::to_string(expected[i]);
  EXPECT_NE(std::string(e.what()).find("non-manifold edge: edge (" + std::to_string(std::min(p, q)) + ", " +
                                       std::to_string(std::max(p, q)) + ") is shared by 14 faces (" + listed +
                                       "), at most 2 allowed"),
            std::string::npos)
      << e.what();
}

TEST(FaceErrors, EachFaceProblemNamesItsFaces) {
  const Arrays good = ico("ico1.off");
  const std::size_t nf = good.f.size() / 3;
  auto faces_of = [&](auto change) {
    Arrays a = good;
    change(a);
    return refusal(a).faces();
  };
  using F = std::vector<std::size_t>;
  EXPECT_EQ(faces_of([](Arrays& a) { a.f[4] = 1000; }), F{1});  // vertex index out of range
  EXPECT_EQ(faces_of([](Arrays& a) { a.f[5] = -1; }), F{1});
  EXPECT_EQ(faces_of([](Arrays& a) { a.f[7] = a.f[6]; }), F{2});  // degenerate face
  // Duplicate: the later face, then the one it repeats, as the message names them.
  EXPECT_EQ(faces_of([](Arrays& a) { a.f.insert(a.f.end(), {a.f[3], a.f[5], a.f[4]}); }), (F{nf, 1}));
  // The faces sharing an edge (two vertices) with face g, from the arrays: on a closed
  // triangle mesh, its three neighbours.
  auto neighbours = [&](std::size_t g) {
    F out;
    for (std::size_t h = 0; h < nf; ++h) {
      int shared = 0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) shared += good.f[3 * h + i] == good.f[3 * g + j];
      if (h != g && shared == 2) out.push_back(h);
    }
    return out;
  };
  // Inconsistent orientation: face 0 flipped; all faces on its three edges (it and its
  // neighbours, each such edge traversed twice the same way), in face order.
  const F flipped = faces_of([](Arrays& a) { std::swap(a.f[1], a.f[2]); });
  F around_0 = neighbours(0);
  around_0.insert(around_0.begin(), 0);
  EXPECT_EQ(flipped, around_0);
  // Open boundary: the last face removed leaves its three neighbours with a boundary edge each.
  const F open = faces_of([](Arrays& a) { a.f.resize(a.f.size() - 3); });
  EXPECT_EQ(open, neighbours(nf - 1));
}

TEST(FaceErrors, AFileReaderRefusalCarriesItsFacesToo) {
  // The file path's checks are the same code: a duplicate face read from a soup.
  const Arrays a = ico("ico1.off");
  std::vector<Point3> points;
  for (std::size_t i = 0; i < a.v.size(); i += 3) points.emplace_back(a.v[i], a.v[i + 1], a.v[i + 2]);
  std::vector<std::vector<std::size_t>> polygons;
  for (std::size_t i = 0; i < a.f.size(); i += 3)
    polygons.push_back({static_cast<std::size_t>(a.f[i]), static_cast<std::size_t>(a.f[i + 1]), static_cast<std::size_t>(a.f[i + 2])});
  polygons.push_back(polygons[3]);
  try {
    check_input_soup("soup", points, polygons);
    ADD_FAILURE() << "accepted";
  } catch (const FaceListError& e) {
    EXPECT_EQ(e.faces(), (std::vector<std::size_t>{polygons.size() - 1, 3}));
    EXPECT_NE(std::string(e.what()).find("duplicate face"), std::string::npos) << e.what();
  }
}

// A non-manifold vertex is refused with the faces around it (before, a plain InputError): two
// tetrahedra that share vertex 0 only, through the file reader and through the arrays.
TEST(FaceErrors, ANonManifoldVertexCarriesTheFacesAroundIt) {
  const std::string path = std::string(test::MESH_DIR) + "/bad/nonmanifold_vertex.off";
  const std::string fans = ": its 6 faces form several fans (the fan through its first face has 3); the surface pinches there";
  const std::vector<std::size_t> around{0, 1, 2, 4, 5, 6};  // face 3 and face 7 do not touch vertex 0
  try {
    read_input_mesh(path);
    ADD_FAILURE() << "accepted";
  } catch (const FaceListError& e) {
    EXPECT_EQ(e.faces(), around);
    EXPECT_EQ(std::string(e.what()), path + ": non-manifold vertex: vertex 0 (line 4)" + fans);
  }
  Arrays a;
  a.v = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, -1, 0, 0, 0, -1, 0, 0, 0, -1};
  a.f = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3, 0, 4, 5, 0, 6, 4, 0, 5, 6, 4, 6, 5};
  const FaceListError e = refusal(a);
  EXPECT_EQ(e.faces(), around);
  EXPECT_EQ(std::string(e.what()), "arrays: non-manifold vertex: vertex 0" + fans);
}

TEST(FaceErrors, RethrowKeepsTheType) {
  try {
    try {
      throw FaceListError("m", {4, 2});
    } catch (const InputError& e) {
      rethrow_input_error(e);
    }
  } catch (const FaceListError& e) {
    EXPECT_EQ(e.faces(), (std::vector<std::size_t>{4, 2}));
    EXPECT_STREQ(e.what(), "m");
  }
}

}  // namespace
}  // namespace shellcontract
