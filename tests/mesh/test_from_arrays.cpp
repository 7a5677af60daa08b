// mesh_from_arrays against read_input_mesh: the same soup from a file and from arrays gives the
// same mesh (corner order included) and the same report, and a bad soup the same problem name.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "mesh/eigen_point_map.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/face_error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/soup_arrays.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

/// A mesh's arrays as the soup that produced it (positions and corner order as written).
using Arrays = test::SoupArrays;
using test::arrays_of;

Mesh from(const Arrays& a, InputReport* report = nullptr, bool reorient = true) {
  TriangleSoupView s;
  s.vertices = a.v.data();
  s.num_vertices = a.v.size() / 3;
  s.faces64 = a.f.data();
  s.num_faces = a.f.size() / 3;
  return mesh_from_arrays(s, "arrays", report, reorient);
}

/// The "<problem>" of an InputError "<name>: <problem>: <details>".
std::string problem_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    const std::string m = e.what();
    const auto a = m.find(": ") + 2;
    return m.substr(a, m.find(": ", a) - a);
  }
  return "(no error)";
}

TEST(FromArrays, SameMeshAndReportAsTheFileReader) {
  for (const char* name : {"ico2.off", "torus.off", "zero_area_face.off"}) {
    InputReport file_report, array_report;
    const Mesh file_mesh = read_input_mesh(std::string(test::MESH_DIR) + "/" + name, &file_report);
    const Arrays a = arrays_of(file_mesh);
    const Mesh mesh = from(a, &array_report);
    const Arrays b = arrays_of(mesh);
    EXPECT_EQ(a.v, b.v) << name;
    EXPECT_EQ(a.f, b.f) << name;
    EXPECT_EQ(array_report.components, file_report.components) << name;
    EXPECT_EQ(array_report.zero_area_faces, file_report.zero_area_faces) << name;
    EXPECT_EQ(array_report.volume, file_report.volume) << name;
    EXPECT_GT(array_report.volume, 0.0) << name;
  }
}

TEST(FromArrays, AMeshAtAnyFiniteScaleIsUsable) {
  // The bounding box's diagonal at 1e160 overflowed in norm() (refused: "the coordinates span
  // more than a double holds") and at 1e-300 underflowed to 0 (refused: "zero bounding-box
  // diagonal"). Scaled by 2^k, a usable mesh stays usable; where its volume is a double, the
  // report's volume scales by 2^3k.
  const Arrays a = arrays_of(read_input_mesh(std::string(test::MESH_DIR) + "/ico2.off"));
  InputReport plain;
  from(a, &plain);
  for (int k : {-1000, -600, -300, 300, 600, 1000}) {
    Arrays scaled = a;
    for (double& c : scaled.v) c = std::ldexp(c, k);
    InputReport report;
    EXPECT_NO_THROW(from(scaled, &report)) << "2^" << k;
    if (std::abs(3 * k) < 1000) {
      EXPECT_NEAR(report.volume / std::ldexp(plain.volume, 3 * k), 1.0, 1e-12) << "2^" << k;
    }
    // Inside out at the same scale: flipped, as at a usual scale (in input units the signed
    // volume overflowed to NaN at 2^600, or to 0 at 2^-600, and the mesh was not flipped).
    Arrays inside_out = scaled;
    for (std::size_t f = 0; f < inside_out.f.size(); f += 3) std::swap(inside_out.f[f + 1], inside_out.f[f + 2]);
    InputReport flipped;
    EXPECT_NO_THROW(from(inside_out, &flipped)) << "2^" << k;
    EXPECT_TRUE(flipped.reoriented) << "2^" << k;
  }
}

/// ico2 and a second copy of it, its vertices mapped by `map`.
template <class Map>
Arrays ico2_and_copy(Map map) {
  const Arrays ico = arrays_of(read_input_mesh(std::string(test::MESH_DIR) + "/ico2.off"));
  Arrays a = ico;
  const std::int64_t n = static_cast<std::int64_t>(ico.v.size() / 3);
  for (std::size_t i = 0; i < ico.v.size(); i += 3) {
    const std::array<double, 3> p = map(ico.v[i], ico.v[i + 1], ico.v[i + 2]);
    a.v.insert(a.v.end(), p.begin(), p.end());
  }
  for (const std::int64_t v : ico.f) a.f.push_back(v + n);
  return a;
}

TEST(FromArrays, AComponentThatEnclosesNoVolumeIsRefused) {
  // The copy flattened onto the plane x = 3: the whole still encloses ico2's volume, but the flat
  // part has no inside: the outside pressure turned it inside out, and the run went on.
  const Arrays flat = ico2_and_copy([](double, double y, double z) {
    return std::array<double, 3>{3.0, y, z};
  });
  const std::size_t faces = flat.f.size() / 6;
  EXPECT_EQ(problem_of([&] { from(flat); }), "component with no volume");
  try {
    from(flat);
    ADD_FAILURE() << "accepted";
  } catch (const FaceListError& e) {
    EXPECT_NE(std::string(e.what()).find("component 1 (" + std::to_string(faces) +
                                         " faces, starting at face " + std::to_string(faces) + ")"),
              std::string::npos)
        << e.what();
    ASSERT_EQ(e.faces().size(), faces);
    EXPECT_EQ(e.faces().front(), faces);
    EXPECT_EQ(e.faces().back(), 2 * faces - 1);
  }
  // The file reader refuses it the same way.
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("shellcontract_flat_component_" + std::to_string(::getpid()) + ".off"))
                               .string();
  test::write_soup_off(path, flat);
  EXPECT_EQ(problem_of([&] { read_input_mesh(path); }), "component with no volume");
  std::filesystem::remove(path);
  // A part a thousand times smaller than the rest is a part, not a flat shell; and a lone flat
  // shell is still named by the whole's volume.
  EXPECT_NO_THROW(from(ico2_and_copy([](double x, double y, double z) {
    return std::array<double, 3>{3.0 + 1e-3 * x, 1e-3 * y, 1e-3 * z};
  })));
  Arrays lone = arrays_of(read_input_mesh(std::string(test::MESH_DIR) + "/ico2.off"));
  for (std::size_t i = 0; i < lone.v.size(); i += 3) lone.v[i] = 0.0;
  EXPECT_EQ(problem_of([&] { from(lone); }), "no positive volume");
}

TEST(FromArrays, Int32FacesGiveTheSameMesh) {
  const Arrays a = arrays_of(read_input_mesh(std::string(test::MESH_DIR) + "/ico2.off"));
  const std::vector<std::int32_t> f32(a.f.begin(), a.f.end());
  TriangleSoupView s;
  s.vertices = a.v.data();
  s.num_vertices = a.v.size() / 3;
  s.faces32 = f32.data();
  s.num_faces = f32.size() / 3;
  EXPECT_EQ(arrays_of(mesh_from_arrays(s, "arrays")).f, a.f);
}

TEST(FromArrays, FacesKeepTheirGivenFirstCorner) {
  // Rotated corners (same orientation): a written face must list them as given.
  Arrays a = arrays_of(read_input_mesh(std::string(test::MESH_DIR) + "/ico2.off"));
  for (std::size_t f = 0; f < a.f.size(); f += 3)
    for (std::size_t r = 0; r < (f / 3) % 3; ++r) std::rotate(a.f.begin() + f, a.f.begin() + f + 1, a.f.begin() + f + 3);
  EXPECT_EQ(arrays_of(from(a)).f, a.f);
}

TEST(FromArrays, InsideOutIsFlippedOnlyWhenAsked) {
  // The file reader flips the inside-out sphere; giving it back reversed must flip it again.
  const Arrays outward = arrays_of(read_input_mesh(std::string(test::MESH_DIR) + "/inside_out_sphere.off"));
  Arrays inward = outward;
  for (std::size_t f = 0; f < inward.f.size(); f += 3) std::swap(inward.f[f + 1], inward.f[f + 2]);
  InputReport report;
  EXPECT_EQ(arrays_of(from(inward, &report)).f, outward.f);
  EXPECT_TRUE(report.reoriented);
  EXPECT_EQ(arrays_of(from(inward, nullptr, /*reorient=*/false)).f, inward.f);
}

TEST(FromArrays, BadSoupsNameTheirProblem) {
  const Arrays good = arrays_of(read_input_mesh(std::string(test::MESH_DIR) + "/ico1.off"));
  auto with = [&](auto change) {
    Arrays a = good;
    change(a);
    return problem_of([&] { from(a); });
  };
  EXPECT_EQ(with([](Arrays&) {}), "(no error)");
  EXPECT_EQ(with([](Arrays& a) { a.v[7] = std::numeric_limits<double>::quiet_NaN(); }), "non-finite coordinate");
  EXPECT_EQ(with([](Arrays& a) { a.v[2] = INFINITY; }), "non-finite coordinate");
  EXPECT_EQ(with([](Arrays& a) { a.f[4] = 42; }), "vertex index out of range");
  EXPECT_EQ(with([](Arrays& a) { a.f[4] = -1; }), "vertex index out of range");
  EXPECT_EQ(with([](Arrays& a) { a.f[4] = a.f[3]; }), "degenerate face");
  EXPECT_EQ(with([](Arrays& a) { a.f.resize(a.f.size() - 3); }), "open boundary");
  EXPECT_EQ(with([](Arrays& a) { std::swap(a.f[1], a.f[2]); }), "inconsistent orientation");
  EXPECT_EQ(with([](Arrays& a) { a.f.insert(a.f.end(), {a.f[0], a.f[2], a.f[1]}); }), "duplicate face");
  EXPECT_EQ(with([](Arrays& a) { a.v.insert(a.v.end(), {0.0, 0.0, 0.0}); }), "isolated vertex");
  EXPECT_EQ(with([](Arrays& a) { a.f.clear(); }), "empty mesh");
}

// A view with counts but no vertex data is refused as the caller's mistake (it was read through
// a null pointer: a segmentation fault), and an empty soup is an empty mesh whatever its
// pointers (it was "set exactly one of faces32 and faces64" when it had none).
TEST(FromArrays, AViewWithoutDataIsRefusedNotRead) {
  const Arrays good = arrays_of(read_input_mesh(std::string(test::MESH_DIR) + "/ico1.off"));
  TriangleSoupView s;
  s.num_vertices = good.v.size() / 3;
  s.faces64 = good.f.data();
  s.num_faces = good.f.size() / 3;
  EXPECT_THROW(mesh_from_arrays(s, "arrays"), std::invalid_argument);
  EXPECT_EQ(problem_of([] { mesh_from_arrays(TriangleSoupView{}, "arrays"); }), "empty mesh");
}

}  // namespace
}  // namespace shellcontract
