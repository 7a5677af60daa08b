// Why the broad phase's pairs per face grow with the resolution (lab/scripts/pair_growth.py,
// lab/pages/pair-growth.md): the candidate pairs of one step, x0 -> x1, counted
//  - with the step's swept boxes (the broad phase's own count);
//  - as the union of the pairs of k sub-intervals' swept boxes [j/k, (j+1)/k] (what a broad
//    phase that slices the step into k parts would find; sound for the straight trajectories of
//    math-spec 10.1, before any response moves a vertex);
//  - with no motion at all (x1 = x0): what the inflation alone gives.
// All boxes are inflated by the collision step's own inflation, broad_phase_inflation of the
// default CollisionOptions (or of --delta D, the run's --delta), in normalized units
// (bounding-box diagonal of the rest mesh 1).
//
// Usage: pair_growth [--delta D] REST START END [K ...]   (meshes in any format read_input_mesh
// reads; START and END two consecutive frames of a run of REST, e.g. its --export-dir frames)
// Prints one JSON object: faces, inflation, and pairs per face for no motion and for each K.
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "collision/broad_phase.hpp"
#include "collision/topology.hpp"
#include "mesh/eigen_point_map.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/simulation_options.hpp"
#include "sim/rest_state.hpp"

namespace {

using namespace shellcontract;

/// Pairs (VF and EE, unique) of the union over k sub-intervals of x0 -> x1.
std::size_t sliced_pairs(const Positions& x0, const Positions& x1, const CollisionTopology& topo,
                         double inflation, int k) {
  std::vector<std::array<int, 3>> all;
  CandidatePairs pairs;
  for (int j = 0; j < k; ++j) {
    const double ta = static_cast<double>(j) / k, tb = static_cast<double>(j + 1) / k;
    const Positions a = x0 + ta * (x1 - x0);
    const Positions b = j + 1 == k ? x1 : Positions(x0 + tb * (x1 - x0));
    find_candidates(a, b, topo, inflation, pairs);
    for (const auto& p : pairs.vertex_face) all.push_back({0, p[0], p[1]});
    for (const auto& p : pairs.edge_edge) all.push_back({1, p[0], p[1]});
  }
  std::sort(all.begin(), all.end());
  return static_cast<std::size_t>(std::unique(all.begin(), all.end()) - all.begin());
}

}  // namespace

int main(int argc, char** argv) {
  CollisionOptions options;
  if (argc > 2 && std::string(argv[1]) == "--delta") {
    char* end = nullptr;
    options.delta = std::strtod(argv[2], &end);
    if (end == argv[2] || *end != '\0' || !(options.delta > 0.0 && options.delta <= 0.1)) {
      std::fprintf(stderr, "pair_growth: --delta must be a number in (0, 0.1], got %s\n", argv[2]);
      return 2;
    }
    argv += 2;
    argc -= 2;
  }
  if (argc < 4) {
    std::fprintf(stderr, "usage: pair_growth [--delta D] REST START END [K ...]\n");
    return 2;
  }
  try {
    const Mesh rest = read_input_mesh(argv[1]);
    const Mesh start = read_input_mesh(argv[2]);
    const Mesh end = read_input_mesh(argv[3]);
    const Positions xr = positions_from_mesh(rest);
    const Faces faces = faces_array(rest);
    if (faces_array(start) != faces || faces_array(end) != faces) {
      std::fprintf(stderr, "pair_growth: START and END must have REST's faces, in its order\n");
      return 2;
    }
    // Normalized units: the rest mesh's bounding-box diagonal is 1 (as in the simulator).
    const double diagonal = (xr.colwise().maxCoeff() - xr.colwise().minCoeff()).norm();
    const Positions x0 = positions_from_mesh(start) / diagonal;
    const Positions x1 = positions_from_mesh(end) / diagonal;
    const CollisionTopology topo = make_collision_topology(faces, static_cast<int>(x0.rows()));
    const double max_abs = std::max({x0.cwiseAbs().maxCoeff(), x1.cwiseAbs().maxCoeff()});
    const double inflation = broad_phase_inflation(options, max_abs);
    const double nf = static_cast<double>(faces.rows());
    std::printf("{\"faces\": %ld, \"inflation\": %.6g, \"static\": %.4f",
                static_cast<long>(faces.rows()), inflation,
                static_cast<double>(sliced_pairs(x1, x1, topo, inflation, 1)) / nf);
    std::printf(", \"static_no_inflation\": %.4f",
                static_cast<double>(sliced_pairs(x1, x1, topo, 0.0, 1)) / nf);
    for (int i = 4; i < argc; ++i) {
      const int k = std::atoi(argv[i]);
      if (k < 1) {
        std::fprintf(stderr, "\npair_growth: K must be a positive integer, got %s\n", argv[i]);
        return 2;
      }
      std::printf(", \"k%d\": %.4f", k,
                  static_cast<double>(sliced_pairs(x0, x1, topo, inflation, k)) / nf);
    }
    std::printf("}\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pair_growth: %s\n", e.what());
    return 1;
  }
  return 0;
}
