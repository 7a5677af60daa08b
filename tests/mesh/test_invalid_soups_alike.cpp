// Invalid soups refused alike by the two entry points of the acceptance rule: mesh_from_arrays
// (Python's arrays) and read_input_mesh (a file), which share soup::accept_triangles. Each soup
// is given to both; the problem, the faces named and (but for what only a file has: its lines,
// "the file has") the message must be the same. test_from_arrays.cpp compares valid soups.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <regex>
#include <string>
#include <vector>

#include "shellcontract/error.hpp"
#include "shellcontract/face_error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/scratch_dir.hpp"
#include "support/soup_arrays.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

using Arrays = test::SoupArrays;

Arrays ico1() { return test::arrays_of_test_mesh("ico1.off"); }

/// A refusal: "<problem>", the rest of the message with the name and file lines left out, and
/// the faces a FaceListError names.
struct Refusal {
  std::string problem, details;
  std::vector<std::size_t> faces;
};

Refusal refusal_of(const std::function<void()>& f, const std::string& name) {
  try {
    f();
  } catch (const FaceListError& e) {
    Refusal r = refusal_of([&] { throw InputError(e.what()); }, name);
    r.faces = e.faces();
    return r;
  } catch (const InputError& e) {
    std::string m = e.what();
    if (m.rfind(name + ": ", 0) == 0) m.erase(0, name.size() + 2);
    const std::size_t colon = m.find(": ");
    Refusal r{m.substr(0, colon), colon == std::string::npos ? "" : m.substr(colon + 2), {}};
    r.details = std::regex_replace(r.details, std::regex(R"( \(line \d+\))"), "");
    return r;
  }
  return {"(accepted)", "", {}};
}

class InvalidSoups : public test::ScratchDirTest {
 protected:
  InvalidSoups() : ScratchDirTest("shellcontract_invalid_soups_") {}

  Refusal from_arrays(const Arrays& a) const {
    TriangleSoupView s;
    s.vertices = a.v.data();
    s.num_vertices = a.v.size() / 3;
    s.faces64 = a.f.data();
    s.num_faces = a.f.size() / 3;
    return refusal_of([&] { mesh_from_arrays(s, "arrays"); }, "arrays");
  }

  Refusal from_file(const Arrays& a) const {
    const std::string path = (dir_ / "soup.off").string();
    test::write_soup_off(path, a);
    return refusal_of([&] { read_input_mesh(path); }, path);
  }
};

struct Case {
  const char* what;
  const char* problem;
  std::function<void(Arrays&)> change;
};

TEST_F(InvalidSoups, AreRefusedAlikeFromArraysAndFromAFile) {
  const Arrays good = ico1();
  const std::size_t nv = good.v.size() / 3;
  const auto drop_last_face = [](Arrays& a) { a.f.resize(a.f.size() - 3); };
  const auto add_vertex = [](Arrays& a) { a.v.insert(a.v.end(), {5.0, 5.0, 5.0}); };
  const auto repeat_face = [](Arrays& a) { a.f.insert(a.f.end(), {a.f[0], a.f[2], a.f[1]}); };
  const std::vector<Case> cases = {
      {"a face less", "open boundary", drop_last_face},
      {"a face flipped", "inconsistent orientation", [](Arrays& a) { std::swap(a.f[1], a.f[2]); }},
      {"a face twice", "duplicate face", repeat_face},
      {"a vertex of no face", "isolated vertex", add_vertex},
      // Both problems: the edges are checked first (soup_checks.hpp); the arrays were refused
      // for the isolated vertex, a file for its open boundary.
      {"a face less and a vertex of no face", "open boundary",
       [&](Arrays& a) { drop_last_face(a), add_vertex(a); }},
      {"a face twice and a vertex of no face", "duplicate face",
       [&](Arrays& a) { repeat_face(a), add_vertex(a); }},
      {"a second sphere through vertex 0", "non-manifold vertex",
       [&](Arrays& a) {
         // The sphere mirrored through vertex 0 (its faces turned to stay outward), sharing that
         // vertex: two fans there. Its other vertices follow the first sphere's.
         const Arrays b = a;
         for (std::size_t i = 3; i < b.v.size(); ++i) a.v.push_back(2 * b.v[i % 3] - b.v[i]);
         for (std::size_t k = 0; k < b.f.size(); k += 3)
           for (const std::size_t c : {k, k + 2, k + 1}) {
             const std::int64_t v = b.f[c];
             a.f.push_back(v == 0 ? 0 : v - 1 + static_cast<std::int64_t>(nv));
           }
       }},
      {"every vertex at one point", "degenerate mesh",
       [](Arrays& a) { std::fill(a.v.begin(), a.v.end(), 0.25); }},
      {"flattened", "no positive volume",
       [](Arrays& a) {
         for (std::size_t i = 0; i < a.v.size(); i += 3) a.v[i] = 0.0;
       }},
      {"a repeated corner", "degenerate face", [](Arrays& a) { a.f[4] = a.f[3]; }},
      {"an index past the vertices", "vertex index out of range",
       [&](Arrays& a) { a.f[4] = static_cast<std::int64_t>(nv); }},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    Arrays a = good;
    c.change(a);
    const Refusal arrays = from_arrays(a), file = from_file(a);
    EXPECT_EQ(arrays.problem, c.problem) << arrays.details;
    EXPECT_EQ(file.problem, arrays.problem) << file.details;
    // An index past the vertices is refused by the OFF reader while it reads (an InputError
    // naming the line, no face list), and worded as the file's count: the problem is the same.
    if (std::string(c.problem) == "vertex index out of range") continue;
    EXPECT_EQ(file.faces, arrays.faces);
    EXPECT_EQ(file.details, arrays.details);
  }
}

}  // namespace
}  // namespace shellcontract
