// Private to the region finder: growing a geodesic disc from a seed while a sphere fits it
// (step 2 of the algorithm in region_selection.hpp).
#pragma once

#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "geometry/cap_internal.hpp"
#include "geometry/curvature.hpp"

namespace shellcontract::detail {

/// What the growth reads of a vertex, packed so that one visit touches one record: its
/// position, its area (a third of the incident faces) and that area again where the smoothed
/// curvature is concave (0 elsewhere).
struct GrowthVertex {
  Vec3 point = Vec3::Zero();
  double area = 0.0, concave_area = 0.0;
};

std::vector<GrowthVertex> growth_vertices(const MeshArrays& m, const Positions& x, const Eigen::VectorXd& concave_field);

/// Grows discs from seeds. Scratch arrays are kept between seeds (reset through the lists of
/// what a growth touched), so a growth costs what it visits, not the mesh's size; one grower
/// per thread.
class CapGrower {
 public:
  CapGrower(const MeshArrays& m, const std::vector<GrowthVertex>& vertices, const CurvatureField& c,
            const RegionOptions& o);

  /// The cap around `seed`, not entering vertices with (*blocked)[v] != 0 (none when blocked
  /// is null). Nothing when no disc passed the tests. The cap's faces are listed only when
  /// want_faces is null or true of the cap (the free growth's flat caps are only counted, and
  /// listing a disc's faces costs as much as growing it).
  std::optional<Cap> grow(int seed, const std::vector<char>* blocked,
                          const std::function<bool(const Cap&)>* want_faces = nullptr);

 private:
  struct State {
    double dist;
    bool popped;
  };
  std::vector<int> disc_faces(int seed, double rho, const std::vector<char>* blocked);
  void reset();

  const MeshArrays& m_;
  const std::vector<GrowthVertex>& v_;
  const CurvatureField& c_;
  const RegionOptions& o_;
  std::vector<State> state_;
  std::vector<char> in_, keep_;  ///< per face, all 0 between calls
  std::vector<int> touched_;
  std::vector<std::pair<double, int>> heap_;
};

}  // namespace shellcontract::detail
