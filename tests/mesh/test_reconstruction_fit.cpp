// The reconstructed surface is checked against its points: CGAL's surface mesher meshes the part
// of the implicit surface around one inner point, so two separate spheres came out as one (exit 0,
// the other's points silently lost), and half the normals flipped gave a closed surface of folds
// and tunnels. Also: the 10-point minimum counts distinct positions, not lines.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "mesh/reconstruction.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

/// n points of a Fibonacci spiral on the unit sphere centred at (cx, 0, 0), "x y z nx ny nz" per
/// line, the normal outward, or inward where `flip(i)`.
template <class Flip>
std::string sphere(int n, double cx, Flip flip) {
  std::ostringstream out;
  out.precision(17);
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < n; ++i) {
    const double phi = std::acos(1.0 - 2.0 * (i + 0.5) / n),
                 theta = pi * (1.0 + std::sqrt(5.0)) * (i + 0.5);
    const double x = std::cos(theta) * std::sin(phi), y = std::sin(theta) * std::sin(phi),
                 z = std::cos(phi);
    const double s = flip(i) ? -1.0 : 1.0;
    out << x + cx << ' ' << y << ' ' << z << ' ' << s * x << ' ' << s * y << ' ' << s * z << '\n';
  }
  return out.str();
}

std::string sphere(int n, double cx = 0.0) {
  return sphere(n, cx, [](int) { return false; });
}

/// The error of reconstructing `text` (written to a temporary file), or "(accepted)".
std::string error_of(const std::string& name, const std::string& text) {
  const fs::path path = fs::temp_directory_path() / ("shellcontract_fit_" + name + ".xyz");
  std::ofstream(path) << text;
  std::string error = "(accepted)";
  try {
    reconstruct_from_oriented_points(path.string());
  } catch (const InputError& e) {
    error = e.what();
  }
  fs::remove(path);
  return error;
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(ReconstructionFit, OneSphereStillReconstructs) {
  EXPECT_EQ(error_of("one", sphere(2000)), "(accepted)");
}

// Before: accepted, a mesh of one sphere.
TEST(ReconstructionFit, TwoSeparateSpheresAreRefusedNamingTheMissedPoints) {
  const std::string e = error_of("two", sphere(2000) + sphere(2000, 3.0));
  EXPECT_TRUE(has(e, "the reconstructed surface misses 2000 of 4000 points") &&
              has(e, "e.g. line ") && has(e, "separate objects (reconstruct them one by one)"))
      << e;
}

// Before: every third normal flipped gave a closed surface with exit 0 (a review's half-flipped set
// gave one of two components and genus 55); half of them flipped at random failed, blamed on the
// points all lying on one sphere, which they also do with good normals. Both are now refused
// before the reconstruction (which on a dense set ran for minutes first); a tenth flipped, below
// that bar, by the check of the surface made.
TEST(ReconstructionFit, InconsistentNormalsAreRefusedNamingTheNormals) {
  const std::string third = error_of("third", sphere(2000, 0.0, [](int i) { return i % 3 == 0; }));
  EXPECT_TRUE(has(third, ": no surface reconstructed: ") &&
              has(third,
                  " of 2000 points have a normal against most of their nearest neighbours' "
                  "(e.g. line 1)") &&
              has(third, "the normals are not consistently oriented"))
      << third;
  const std::string tenth = error_of("tenth", sphere(2000, 0.0, [](int i) { return i % 8 == 0; }));
  EXPECT_TRUE(has(tenth,
                  "250 of 2000 normals point into the reconstructed surface: the normals are "
                  "not consistently oriented (e.g. line 1: point"))
      << tenth;
  std::mt19937 rng(1);
  std::bernoulli_distribution coin(0.5);
  const std::string half = error_of("half", sphere(2000, 0.0, [&](int) { return coin(rng); }));
  EXPECT_TRUE(
      has(half, ": no surface reconstructed: ") &&
      has(half, "points have a normal against most of their nearest neighbours' (e.g. line ") &&
      has(half, "the normals are not consistently oriented") && !has(half, "one sphere"))
      << half;
  // All of them inward is a consistent set: the surface comes out (turned outward) as before.
  EXPECT_EQ(error_of("inward", sphere(2000, 0.0, [](int) { return true; })), "(accepted)");
}

// Before: 9 points given twice each were accepted (the lines were counted); 9 once were refused
// as "only 9 points; need an oriented point set", without the minimum.
TEST(ReconstructionFit, NineDistinctPointsAreTooFewWhateverTheLines) {
  const std::string nine = sphere(9);
  EXPECT_TRUE(has(error_of("nine", nine), ": 9 distinct points; at least 10 are needed"))
      << error_of("nine", nine);
  const std::string twice = error_of("nine_twice", nine + nine);
  EXPECT_TRUE(has(twice, ": 9 distinct points (on 18 lines); at least 10 are needed")) << twice;
}

}  // namespace
}  // namespace shellcontract
