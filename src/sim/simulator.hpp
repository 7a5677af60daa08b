// The library's one entry point for a contraction run (architecture.md data flow): normalized rest
// state, then the time loop of math-spec 2 (paper Steps 1-7).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "collision/self_collision.hpp"
#include "mesh/normalization.hpp"
#include "pbd/solver.hpp"
#include "shellcontract/mesh.hpp"
#include "shellcontract/observer.hpp"
#include "shellcontract/simulation_options.hpp"
#include "shellcontract/types.hpp"
#include "sim/anisotropy.hpp"
#include "sim/dimple_rest.hpp"
#include "sim/mass_scaling.hpp"
#include "sim/pressure.hpp"
#include "sim/region_dimple.hpp"
#include "sim/rest_state.hpp"
#include "sim/run_plan.hpp"
#include "sim/simulator_state.hpp"

namespace shellcontract {

/// Runs the contraction of one closed mesh.
class Simulator {
 public:
  /// Builds the rest state and the constraints of a plan (run_plan.hpp): the plan's options are
  /// resolved and checked, its mesh normalized with its regions in "f:region"; the Simulator
  /// neither checks nor resolves.
  /// @throws InputError for an unusable mesh (no positive enclosed volume)
  explicit Simulator(SimPlan plan);
  /// Simulator(plan_simulation(input, options)): the regions are the map `input` carries.
  /// @param input  a checked, closed, outward-oriented triangle mesh (read_input_mesh), any units
  /// @throws UsageError for invalid options, InputError for an unusable mesh
  Simulator(Mesh input, const SimOptions& options);
  ~Simulator();

  /// One time step: predict with the pressure force, project constraints, update velocities.
  /// @throws SimulationError on non-finite positions; the state is then left at the last good step
  FrameMetrics step();

  /// True when the frame count is reached or the step reached options.stop_volume_ratio.
  bool finished() const;

  /// The target V/V0 of the volume constraint at frame n (the ramp of options.target_volume, or
  /// options.target_volume_schedule at n when that has keys);
  /// 0 without a target volume.
  double volume_target(int n) const;
  /// The pressure P of the step from frame n to n + 1: options.pressure, or its schedule's value
  /// at frame n (options.pressure_schedule).
  double pressure_at(int n) const;
  /// The net over-pressure that acts on the current state: pressure_at(frame()) with the
  /// enclosed air at the current volume (air_net_pressure), the P the next step applies
  /// (> 0 pushes inward). Without the local contraction's region load.
  double net_pressure() const;
  /// Whether a step reached options.stop_volume_ratio (the run then ends on it): its V/V0 after
  /// the collision response is at most epsilon, or at most epsilon + target_volume_tolerance
  /// where the step's prediction crossed epsilon and was projected onto it.
  bool stop_volume_reached() const { return stop_volume_reached_; }

  int frame() const { return frame_; }
  double volume_ratio() const { return volume_ratio_; }
  /// Current positions, normalized units, row i = vertex i.
  const Positions& positions() const { return x_; }
  /// Current positions scaled back to the input's units.
  Positions positions_in_input_units() const { return denormalize(x_, normalization_); }
  /// The normalized rest mesh with the rest-state property maps.
  const Mesh& rest_mesh() const { return *mesh_; }
  const Normalization& normalization() const { return normalization_; }
  const RestStateReport& rest_report() const { return rest_report_; }
  /// Vertices whose mass scale_masses_for_pressure raised (sim/mass_scaling.hpp).
  std::size_t mass_scaled_vertices() const { return mass_scaling_.raised; }
  /// What the explicit pressure's mass floor did: how many masses, by how much, and the step
  /// below which it would raise none (sim/mass_scaling.hpp).
  const MassScaling& mass_scaling() const { return mass_scaling_; }
  /// The inverse vertex masses the steps use: area-lumped or unit, with the floors of
  /// build_rest_state and the pressure's mass scaling (0: pinned).
  const Eigen::VectorXd& inv_masses() const { return inv_mass_; }
  /// The faces, row j = face j's vertices, counter-clockwise from outside.
  const Faces& faces() const { return faces_; }
  const AnisotropyReport& anisotropy_report() const { return anisotropy_report_; }
  /// Number of regions in the rest mesh's "f:region" map, whether or not anything acts on them.
  std::size_t region_count() const { return region_count_; }
  /// Face pairs that already intersect in the input (the validation baseline).
  std::size_t input_intersections() const;
  /// Primitive pairs the collision handling ignores because they touch in the rest state.
  std::size_t excluded_contact_pairs() const {
    return collision_ ? collision_->excluded_pairs() : 0;
  }
  /// CGAL self-intersection check of the current positions: face pairs not in the input's set.
  std::size_t count_new_intersections() const;
  /// How far the anisotropic regions sank in: the mean over the vertices of every region
  /// (the "f:region" map, whether or not E_A is on) of -(x_i - xbar_i) . nbar_i, with
  /// nbar_i the rest area-weighted unit vertex normal (normalized units; > 0 = moved inward).
  /// 0 when there are no regions. The paper's Fig. 20 measure (issue acceptance).
  double region_inward_displacement() const;
  /// region_inward_displacement() of each region alone, in the regions' order: a region that
  /// does not sink shows here even when the others carry the mean.
  std::vector<double> region_sinks() const;
  /// How far the rest of the shell moved: the mean |x_i - xbar_i| over the vertices outside the
  /// regions and outside the one-ring band around them (normalized units; 0 when there are no
  /// regions). region_inward_displacement() over it is the local contraction's locality.
  double outside_region_displacement() const;
  /// Regions the Volume local contraction leaves alone because they are flat or dented at rest
  /// (no cap to shrink).
  int regions_without_cap() const { return regions_without_cap_; }
  const SimOptions& options() const { return options_; }
  /// Energies at the current positions.
  ConstraintEnergies energies() const { return solver_->energies(x_); }
  /// Elastic (membrane + anisotropic) energy of each face at the current positions.
  Eigen::VectorXd face_energies() const { return solver_->face_energies(x_, faces_.rows()); }
  /// Normalized rest positions.
  const Positions& rest_positions() const { return rest_x_; }

  /// Everything the next steps depend on besides what the constructor builds (a checkpoint,
  /// sim/checkpoint.hpp). Between steps.
  SimulatorState state() const;
  /// Continues from a state() of a Simulator built from the same mesh and options: the next
  /// step() is the one the saving Simulator would have taken.
  /// @throws InputError if the state's sizes do not fit this mesh
  void restore(SimulatorState state);

 private:
  /// Projects x onto the volume of a target-volume run, or onto the stop ratio at its crossing.
  void apply_volume_control(Positions& x);
  /// Projects each region's dimple onto its mirror image of this frame (InwardTerm::Volume).
  void apply_region_contraction(Positions& x);
  /// set_dimple_size of dimple i, and under DimpleShape::Mirror its dimpled rest shape
  /// (set_dimple_rest) when the size changes.
  void resize_dimple(std::size_t i, int size);
  /// Takes the outside vertices' rigid step (shift and turn) out of x (follow_rest_frame).
  void follow_rest(Positions& x) const;

  /// The run's threads for the step's own per-vertex work (simulator.cpp).
  struct StepArena;

  SimOptions options_;
  std::unique_ptr<StepArena> arena_;
  std::unique_ptr<Mesh> mesh_;
  Normalization normalization_;
  RestStateReport rest_report_;
  AnisotropyReport anisotropy_report_;
  Faces faces_;
  VertexFaces faces_around_;  ///< the faces around each vertex, for the pressure
  Faces inward_faces_;      ///< anisotropic faces that get the local extra pressure
  Positions region_force_;  ///< its forces (buffer)
  std::vector<RegionDimple> region_dimples_;  ///< InwardTerm::Volume: the regions' pieces with a cap to sink
  /// [i]: what dimple i's dimpled rest state changed in the solver (set_dimple_rest)
  std::vector<DimpleRestChange> dimple_rest_;
  HingeIndex hinge_index_;  ///< the solver's hinges by edge (set_dimple_rest)
  int regions_without_cap_ = 0;         ///< regions left alone: flat or dented at rest
  /// Weighted regions (sim/region_weights.hpp): each dimple's strength factor, the rest
  /// area-weighted mean of its faces' weights, and each inward face's weight; 1 and empty
  /// without weights.
  std::vector<double> dimple_weight_;
  Eigen::VectorXd inward_weight_;
  /// A local contraction acts (caps or region force): the frame follows the rest of the shell.
  /// A free shell whose regions sink in recoils as a whole (its centre of mass stays), which on
  /// bumpy_sphere was nearly all of the rest's displacement (docs/math/local-contraction.md).
  bool follow_rest_ = false;
  Eigen::VectorXd inv_mass_;
  MassScaling mass_scaling_;
  std::unique_ptr<ConstraintSolver> solver_;
  std::unique_ptr<SelfCollision> collision_;
  /// Input's intersecting face pairs, computed on first use (validation only).
  mutable std::optional<std::vector<std::pair<FaceIndex, FaceIndex>>> baseline_intersections_;
  Positions x_, v_, x_pred_, force_;
  Positions rest_x_;                  ///< normalized rest positions
  std::size_t region_count_ = 0;
  std::vector<int> region_vertices_;  ///< vertices of the regions, sorted, unique
  std::vector<int> outside_vertices_;  ///< neither in a region nor in its one-ring band
  Positions region_normals_;          ///< their rest unit normals, same order
  /// Per region, the indices into region_vertices_ of its vertices.
  std::vector<std::vector<std::size_t>> region_members_;
  /// -(x_v - xbar_v) . nbar_v of region vertex i (an index into region_vertices_).
  double inward_displacement(std::size_t i) const;
  double rest_volume_ = 0.0;
  double constraint_rest_volume_ = 0.0;  ///< V0 as signed_volume computes it (the constraint's)
  bool stop_volume_reached_ = false;
  bool stop_volume_crossed_ = false;   ///< this step's prediction crossed the stop ratio
  Positions before_collisions_;        ///< volume control: positions before the response
  std::vector<char> held_by_contact_;  ///< volume control: moved by the last step's response
  double volume_ratio_ = 1.0;
  int frame_ = 0;
};

}  // namespace shellcontract
