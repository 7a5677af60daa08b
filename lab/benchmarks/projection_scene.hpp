// The scene that the projection kernels are timed on: one for bench_projection and for
// lab/kernels/dihedral_ab.cpp, so that the A/B of a kernel times the same work as the benchmark
// it is compared with (the same mesh normalization, compression and perturbation).
#pragma once

#include <random>
#include <string>

#include <Eigen/Core>

#include "shellcontract/mesh_io.hpp"
#include "sim/rest_state.hpp"
#include "sim/simulator.hpp"

namespace shellcontract::lab {

/// Constraints of the normalized mesh and a compressed, perturbed state.
struct ProjectionScene {
  ConstraintSet membranes_and_isometric;
  ConstraintSet dihedral;
  Eigen::VectorXd w;
  Positions x;
};

/// The scene of the mesh at `path`: the simulator's rest mesh (normalized as a run has it), its
/// constraints for both bending models, and positions at 0.9 of the rest shape with a fixed-seed
/// noise of 1e-3, so that every projection moves its vertices (a state at rest would make
/// most projections return early) and every run times the same state.
/// @throws what read_input_mesh throws for an unreadable mesh
inline ProjectionScene make_projection_scene(const std::string& path) {
  ProjectionScene sc;
  const Mesh mesh = read_input_mesh(path);
  SimOptions opt;
  opt.frames = 0;
  Simulator sim(mesh, opt);
  sc.membranes_and_isometric = pack_constraints(sim.rest_mesh(), BendingModel::Isometric);
  sc.dihedral = pack_constraints(sim.rest_mesh(), BendingModel::Dihedral);
  sc.w = inverse_masses(sim.rest_mesh());
  std::mt19937 rng(1);
  std::normal_distribution<double> n(0.0, 1e-3);
  sc.x = 0.9 * sim.positions();
  for (Eigen::Index i = 0; i < sc.x.size(); ++i) sc.x.data()[i] += n(rng);
  return sc;
}

}  // namespace shellcontract::lab
