// The physics settings of a run (RunOptions::sim, shellcontract/options.hpp), each module's in
// its own section: the broad phase and the collision handling, the material's parameters, the
// solver, the anisotropy, the air pressure, keyframed values, and SimOptions that gathers them.
// Plain data: no mesh, solver or collision classes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "shellcontract/types.hpp"

namespace shellcontract {

/// Broad-phase algorithm. All of them return exactly the same pairs (tests compare each with
/// brute force); they differ only in speed.
enum class BroadPhaseMethod {
  /// CGAL box_intersection_d on primitive boxes: vertex boxes against face boxes (bipartite
  /// mode), edge boxes against themselves (complete mode).
  PrimitiveBoxes,
  /// CGAL box_intersection_d on face boxes (complete mode), then the 6 VF and 9 EE pairs of every
  /// overlapping face pair, box-tested and deduplicated (math-spec 10.2, the paper's way).
  FacePairs,
  /// Our own bounding-volume hierarchy (median split, rebuilt each call) over face boxes and
  /// over edge boxes; one query per vertex box and per edge box. Output comes out grouped by
  /// the first id, so only short runs need sorting and nothing needs deduplicating.
  Bvh,
  /// Uniform grid (cell size 3 x the median face/edge box extent, 1.5 x where such cells hold
  /// too many boxes) filled by a counting sort; in each cell, vertex boxes against face boxes
  /// and edge boxes against each other, each pair emitted only in the first cell the two boxes
  /// share (no hash set), culled by a vectorized test on boxes rounded outward to float,
  /// confirmed by the exact double test (with AVX-512, checked at run time, 16 float lanes at a
  /// time, then one exact test per emitted pair). The cells emit the pairs in cell order;
  /// find_candidates then sorts them (see CandidatePairs), so their order does not depend on the
  /// cell size or on a grid kept from the last call. Falls back to PrimitiveBoxes when the boxes
  /// are so large or spread out that the grid would degenerate towards brute force
  /// (BroadPhaseStats::method_run says which ran).
  /// The default: fastest on bear (bench_broad_phase).
  Grid,
};

/// The method find_candidates uses when none is given (the fastest on bear, bench_broad_phase).
static constexpr BroadPhaseMethod DEFAULT_BROAD_PHASE_METHOD = BroadPhaseMethod::Grid;

/// Counters of one find_candidates call (for logs and the paper's Table 2).
struct BroadPhaseStats {
  std::int64_t no_culling_vertex_face = 0;  ///< topo.all_vertex_face_pairs
  std::int64_t no_culling_edge_edge = 0;    ///< topo.all_edge_edge_pairs
  /// Overlapping box pairs the box search reported, adjacent ones included. PrimitiveBoxes:
  /// VF + EE primitive box pairs. FacePairs: face box pairs. Bvh: VF box pairs plus EE box
  /// pairs with a < b. Grid: VF plus EE (a < b) pairs whose boxes overlap after rounding outward
  /// to float (a superset of the exact overlaps, in practice equal), in both the portable and
  /// the AVX-512 cell loop (the latter confirms each pair with the exact test afterwards).
  std::int64_t box_overlaps = 0;
  /// The algorithm that ran: the requested one, except that Grid falls back to PrimitiveBoxes
  /// when its grid would degenerate (see BroadPhaseMethod::Grid).
  BroadPhaseMethod method_run = DEFAULT_BROAD_PHASE_METHOD;
  std::int64_t vertex_face = 0;  ///< VF pairs emitted
  std::int64_t edge_edge = 0;    ///< EE pairs emitted
  double seconds = 0.0;          ///< wall time of the call, s
};

}  // namespace shellcontract

// Options of the collision handling, and the broad-phase inflation they imply (plain data, not
// the collision classes).
namespace shellcontract {

/// Options of the collision handling (normalized units: bounding-box diagonal 1).
struct CollisionOptions {
  /// delta: contact distance. Primitives that come closer than delta during a step are pushed
  /// apart to 2 delta (math-spec 10.8, 14: paper value 1e-4, here relative to the diagonal).
  double delta = 1e-4;
  int rounds = 5;  ///< N_c detection/response rounds before the fail-safe (math-spec 10.8)
  BroadPhaseMethod method = DEFAULT_BROAD_PHASE_METHOD;
  /// Threads of the broad phase's cell loop, the filter and the narrow phase (0 = all cores).
  /// Results do not depend on it.
  int threads = 0;
  /// Warm start: before detection, push the end positions apart along the frozen frames of the
  /// previous step's contacts, detected or still pressed (resting contact persists from step to
  /// step, see SelfCollision::resolve), so that detection finds and pushes fewer pairs.
  /// Detection and the fail-safe still decide; off gives the plain per-step response of
  /// math-spec 10.8.
  bool warm_start = true;
  /// m / delta >= 0: the step's broad phase inflates by (delta + m)/2 (broad_phase_inflation), and
  /// the response keeps each vertex within m/2 of its swept box (see SelfCollision::resolve;
  /// the trade it sets is measured in lab/history.md, "region_margin").
  double region_margin = 4.0;
  /// Speculative broad phase: predict() builds the step's broad phase on predicted end positions
  /// on a spare thread while the constraint solve runs, and resolve() completes it for the
  /// actual ones (see predict). The candidate pairs are the same as without it, but their order
  /// differs (and pairs far apart are always flagged, also where the plain grid falls back to
  /// CGAL), so the step's result can differ in its last bits; it never depends on the thread
  /// count. Off, or when predict is not called, resolve runs the broad phase itself. The
  /// Simulator sets it from SimOptions::speculative_broad_phase.
  bool speculative = true;
  /// After a response push, the passes that mark the pairs of the moved vertices and collect
  /// the next tests visit only the pairs around the step's moved vertices while no other vertex
  /// moves (see Rescan::collect, src/collision/self_collision/rescan.hpp); off, every pass
  /// visits every live pair.
  /// The same tests in the same order either way, so the result does not depend on it.
  bool narrow_rescans = true;
};

/// The broad phase's inflation of every swept box, for coordinates of magnitude at most max_abs
/// (the largest |coordinate| of the step's start and end positions): (delta + m)/2 plus a
/// rounding margin of 4u (max_abs + delta + m), m = region_margin * delta, u the unit roundoff.
/// Two boxes grown by it overlap whenever the step can bring their primitives within delta with
/// every vertex inside its region (see SelfCollision::resolve), so every such pair is a candidate
/// (the argument, rounding included, is at its definition,
/// src/collision/self_collision/step_broad_phase.cpp).
double broad_phase_inflation(const CollisionOptions& options, double max_abs);

}  // namespace shellcontract

// The material's settings as plain data: which membrane and fibre energies, and their
// parameters (not the material classes: shellcontract/material.hpp).
namespace shellcontract {

/// Isotropic membrane energy E_S (math-spec 6). Names: "stvk", "corotated", "linear",
/// "mooney-rivlin".
enum class MaterialKind { Stvk, Corotated, Linear, MooneyRivlin };

/// Anisotropic fibre energy E_A (math-spec 7). Names: "none", "arap", "stvk", "sqrt",
/// "active-fiber". Each model's name() equals its name here.
enum class AnisoKind { None, Arap, Stvk, Sqrt, ActiveFiber };

/// Membrane stiffness parameters. Units: energy per unit rest area (N/m for a membrane in SI).
struct MaterialParams {
  double mu = 1.0;           ///< shear modulus (Lame mu), default 1 (math-spec 14)
  double lambda = 1.0;       ///< plane-stress Lame lambda, default lambda/mu = 1 (math-spec 14)
  double c10 = 0.5;          ///< Mooney-Rivlin C10, default mu/2 (math-spec 14)
  double c01 = 0.0;          ///< Mooney-Rivlin C01, default 0 (neo-Hookean membrane)
  double mu_aniso = 1.0;     ///< anisotropic fibre stiffness mu_A
  double fiber_target = 1.0; ///< active-fibre target stretch gamma in (0, 1] (math-spec 7)
};

}  // namespace shellcontract

// The constraint solver's settings as plain data (not the solver, src/pbd/solver.hpp).
namespace shellcontract {

/// pbd: the paper's energy-as-constraint projection (C = E); xpbd: C = sqrt(2E) with compliance,
/// so stiffness has physical meaning (math-spec 9.1, 9.2).
enum class SolverKind { Pbd, Xpbd };

/// Order of the Gauss-Seidel sweep inside each kind of constraint (math-spec 9.4).
enum class ConstraintOrder {
  /// Array order of the ConstraintSet (the paper's sequential Gauss-Seidel), single thread.
  Sequential,
  /// Constraints grouped by a greedy vertex colouring (no two of one colour share a vertex),
  /// colours in sequence, each colour's constraints in parallel (TBB). A different but equally
  /// valid Gauss-Seidel order; its result does not depend on the number of threads (bit-identical).
  Coloured,
};

/// Solver settings (defaults: the paper's values where it gives them, math-spec 14).
struct SolverSettings {
  SolverKind kind = SolverKind::Pbd;
  int iterations = 5;        ///< Gauss-Seidel sweeps per step (paper: 5)
  double k_bending = 0.01;   ///< k_B: PBD correction multiplier / XPBD energy scale (9.5)
  double dt = 0.01;          ///< time step (normalized units), used by XPBD's alpha/dt^2
  AnisoKind aniso = AnisoKind::None;  ///< E_A model on ConstraintSet::anisotropic
  /// Paper's k_A term inside the E_A projection (math-spec 9.3; PBD only). When false, k_A is
  /// applied as an explicit force by the simulator (math-spec 9.2 R) or not at all.
  bool k_a_in_projection = true;
  /// Inversion-aware orientation s = sign(n . n_ref) for the E_A faces (math-spec 4.2 option);
  /// default s = +1.
  bool inversion_aware = false;
  /// Sweep order; Sequential is one fixed Gauss-Seidel order (the paper names none), one thread.
  ConstraintOrder order = ConstraintOrder::Sequential;
  /// Threads of the Coloured order (0 = TBB's default, the machine's cores); ignored by
  /// Sequential. Must be >= 0.
  int threads = 0;
};

}  // namespace shellcontract

// The anisotropic regions' settings as plain data (fibre directions, k_A), not the anisotropy setup
// (src/sim/anisotropy.hpp, which needs the mesh). Which faces are regions is not an option here:
// the run plan resolves it into the mesh's "f:region" map (sim/run_plan.hpp).
namespace shellcontract {

/// How the fibre direction a of a region face is chosen (the paper never gives one).
enum class FiberMode {
  /// Tangent direction from the face toward its region's area-weighted centre: shortening along it
  /// pulls the region together (default; docs/design/anisotropy.md "Fibre direction" gives the
  /// measurement).
  TowardCentre,
  /// One user 3D direction d for every face: a = normalize(d . T1, d . T2) (math-spec 7).
  User,
};

/// Options of the anisotropic regions.
struct AnisotropyOptions {
  FiberMode fiber_mode = FiberMode::TowardCentre;
  Vec3 user_direction = Vec3::UnitX();    ///< FiberMode::User only
  double kappa_a = 0.1;                   ///< k_A = kappa_A mu_A sqrt(Abar_j) (math-spec 9.3, 14)
  double mu_aniso = 1.0;                  ///< mu_A, for k_A
};

}  // namespace shellcontract

// Which pressure force a run applies, as plain data (not the pressure module,
// src/sim/pressure.hpp).
namespace shellcontract {

/// energy: f_i = -(P/6) sum_{j ni i} N_j = -P dV/dx_i (default; no net force, work = -P dV).
/// paper:  f_i = -P nhat_i sum_{j ni i} A_j / 3 with the area-weighted unit vertex normal
///         (paper eq. for Step 1; same direction, larger magnitude on coarse meshes).
enum class PressureModel { EnergyConsistent, Paper };

}  // namespace shellcontract

// A value that follows keyframes over the frames of a run (--target-volume "0:1, 60:0.5, 120:0.85",
// -p "0:4, 100:0"): the keys as an animator sets them, smooth between them, constant outside.
// docs/design/keyframes.md.
namespace shellcontract {

/// One key: the value at a frame (frame 0 is the rest state, frame n the state after step n).
struct Keyframe {
  int frame = 0;
  double value = 0.0;
};

/// A value over the frames, interpolated between keys by a monotone cubic Hermite curve
/// (Fritsch-Carlson slopes, the weighted harmonic mean of the neighbouring secants as in PCHIP),
/// with zero slope at the first and last key and at every key where the curve turns:
///  - between two keys the value stays between theirs (no overshoot, so a valid range of the keys
///    is valid everywhere, and a held value, two equal keys, is exactly constant);
///  - the curve is C1: the shell is never asked for a jump in speed;
///  - two keys alone give the smoothstep 3t^2 - 2t^3 of the single-number target ramp.
/// Before the first key the value is the first key's, after the last the last key's.
class Schedule {
 public:
  Schedule() = default;
  /// @param keys  frames >= 0 and strictly increasing, values finite -- not checked here;
  ///              parse_schedule is the checking constructor, and a run refuses a schedule
  ///              whose keys break these rules (resolve_run_options)
  explicit Schedule(std::vector<Keyframe> keys);

  bool empty() const { return keys_.empty(); }
  const std::vector<Keyframe>& keys() const { return keys_; }
  /// The value at `frame` (any real frame; the run asks at integer frames).
  double at(double frame) const;
  double first_value() const { return keys_.front().value; }
  double last_value() const { return keys_.back().value; }
  int last_frame() const { return keys_.back().frame; }
  double min_value() const;
  double max_value() const;
  /// "0:1, 60:0.5, 120:0.85", each value in the shortest text that reads back exactly: parsing
  /// it gives the same schedule.
  std::string text() const;

  bool operator==(const Schedule& o) const;
  bool operator!=(const Schedule& o) const { return !(*this == o); }

 private:
  std::vector<Keyframe> keys_;
  std::vector<double> slopes_;  ///< dv/dframe at each key
};

/// What a key's value may be, for the messages: lo/hi with open or closed ends, and how the
/// message says it ("a ratio in (0, 2]").
struct KeyRange {
  double lo = 0.0, hi = 0.0;
  bool lo_open = false, hi_open = false;
  std::string text;
  bool contains(double v) const;
};

/// Whether an option's text is a schedule ("F:V, ...") rather than one number.
bool is_schedule_text(const std::string& text);

/// Parses "F:V, F:V, ..." (whitespace around the numbers is free; frames are integers >= 0,
/// strictly increasing; values in `range`).
/// @param option  the option's CLI name, for the messages ("target-volume")
/// @throws UsageError "--OPTION: key K ('TEXT'): what is wrong" (K counts from 1)
Schedule parse_schedule(const std::string& option, const std::string& text, const KeyRange& range);

/// The schedule of a target volume: parse_schedule with `range`, and frame 0 is the rest state,
/// V/V0 = 1: a first key at frame 0 must be 1 (a jump in one step would tear the shell), and a
/// first key after frame 0 gets the key 0:1 before it, so the shell eases from its rest volume.
/// @throws UsageError naming the key
Schedule parse_volume_schedule(const std::string& option, const std::string& text,
                               const KeyRange& range);

}  // namespace shellcontract

// Plain option structs of a simulation run. Defaults are the paper's values where it gives
// them, otherwise ours (math-spec 14); README.md "Options" documents how they were chosen.
// Plain data gathering the sections above (no mesh, solver, collision or material classes); the
// run plan (src/sim/run_plan.hpp) resolves and checks them.
namespace shellcontract {

/// isometric: the paper's flat-rest model (math-spec 8.2); dihedral: rest-aware (8.3).
enum class BendingModel { Isometric, Dihedral, None };

/// The local contraction's mechanism on the regions: Volume (default) sinks each region as a
/// mirrored dimple around its apex, as large as region_shrink asks, and holds it there
/// (region_dimple.hpp, docs/math/local-contraction.md): the region sinks a chosen amount and the
/// rest of the shell is left alone once it is there; under a global pressure its faces also take
/// the region load REGION_LOAD_GAIN S P (local_contraction.hpp). Force is the paper's extra
/// pressure P_A on the region faces, f_i = -(P_A/6) sum N_j, applied in the prediction without
/// net force or torque (math-spec 9.2 R); it keeps pushing for the whole run, so the sink creeps
/// on and spreads to the rest.
/// Projection is the paper's k_A inside the E_A projection (math-spec 9.3; PBD only, in XPBD it
/// becomes Force). None: no inward term.
enum class InwardTerm { Projection, Force, Volume, None };

/// The shape InwardTerm::Volume drives each region's dimple to: Volume projects the dimple's cap
/// volume only (region_volume.hpp); Mirror (the default) moves its interior vertices onto the
/// mirror image of the rest cap through the rim's plane, an isometry, carried by the shell away
/// from the regions, the ring at the rim left to the solver and a vertex already deeper left
/// where it is (region_mirror.hpp, docs/math/region-mirror.md), and keeps the volume projection
/// for a region that cannot be mirrored.
enum class DimpleShape { Volume, Mirror };

/// Default strength of the local contraction (SimOptions::region_shrink, in [0, 1]): with the
/// Volume mechanism, a region on a shell at its rest volume loses 2 * 0.7 = 1.4 times its rest cap
/// volume, as a mirrored dimple (dimple_rest_volume). Chosen by measurement
/// (lab/pages/local-contraction.md, section 2): at -p 0 the ratio of the regions' sink to the
/// rest's motion on bumpy_sphere is largest near this strength; 1 sinks deeper but moves the rest
/// more, so the dimple is less local.
inline constexpr double DEFAULT_REGION_SHRINK = 0.7;

/// When CGAL's self-intersection test checks the result (new intersections vs the input's).
enum class ValidateMode { Off, End, EveryFrame };

/// area: m_i = rho_A sum Abar_j / 3 (math-spec 1.4, default); unit: m_i = 1.
enum class MassModel { AreaLumped, Unit };

/// Default net over-pressure at the rest volume, normalized units. Chosen with the default air
/// (DEFAULT_AIR_BALANCE) and dihedral bending by measurement (docs/design/defaults.md): 200 default
/// frames end between V/V0 0.4 and 0.8 on eight, hand, elk, bear and the kitten.
inline constexpr double DEFAULT_PRESSURE = 4.0;

/// Default balance volume ratio of the enclosed air (air_net_pressure): the net pressure vanishes
/// at V/V0 = 0.5, so that every mesh slows down and stops short of being crushed, whatever its
/// shape or resolution (docs/design/defaults.md).
inline constexpr double DEFAULT_AIR_BALANCE = 0.5;

/// Default length of the target-volume ramp, in frames: long enough that the shell follows the
/// shrinking volume quasi-statically, short enough to hold the target for most of a default run.
inline constexpr int DEFAULT_TARGET_RAMP_FRAMES = 100;

/// Smallest time step: XPBD divides by dt^2, which underflows below about 1e-154 (a run with
/// --dt 1e-155 turned every position into NaN at its first step).
inline constexpr double MIN_DT = 1e-100;

/// Smallest areal density: a vertex's mass is the density times a share of the normalized
/// surface, and its inverse must be a finite number (a density of 1e-310 gave masses of 0 and
/// infinite inverse masses: NaN positions at the first step, with no word of why). The bound
/// leaves some 200 orders of magnitude for the finest mesh's share before that happens.
inline constexpr double MIN_DENSITY = 1e-100;

/// Largest V/V0 a key of a keyframed target volume may ask: re-inflation to the rest volume and
/// beyond it up to twice the volume; a larger ratio is taken for a typo (50 for 0.5).
inline constexpr double MAX_KEYED_VOLUME_RATIO = 2.0;

/// Default fraction of the velocity removed per step of the paper's PBD solver (--solver pbd).
/// The paper has no damping; without it the undamped PBD shell rings (V/V0 oscillates around its
/// quasi-static path, README measurement).
inline constexpr double DEFAULT_DAMPING = 0.2;

/// The default run's damping (XPBD with the default shell material, RunOptions). Half the PBD
/// value, chosen when it made the regions' sink more local than 0.2; with today's dimple that
/// reason no longer holds on every mesh, and 0.1 stays as the value the goldens and the documented
/// V/V0 are pinned at until a change of default is measured on its own (docs/design/defaults.md,
/// "Why damping 0.1").
inline constexpr double DEFAULT_XPBD_DAMPING = 0.1;

/// The default run's shell material (XPBD, RunOptions): Young's modulus and thickness in
/// normalized units (bounding-box diagonal 1), Poisson ratio 0.3. Chosen by measurement
/// (docs/design/defaults.md "The default run"): icospheres of 320 to 20,480 faces end within
/// 0.02 of each other and bear with bear split in four within 0.03, and the wrinkles take a size
/// set by the thickness (lab/pages/wrinkles.md).
inline constexpr double DEFAULT_SHELL_YOUNG = 1000.0;
inline constexpr double DEFAULT_SHELL_THICKNESS = 0.002;

/// Whether the collision broad phase starts speculatively while the constraint solve runs
/// (CollisionOptions::speculative, SelfCollision::predict). Its task runs on the core that a
/// single-threaded solve leaves idle; a parallel solve needs that core itself, and the task
/// slows both the solve and the step there (lab/history.md).
enum class SpeculativeBroadPhase {
  Auto,  ///< on with the sequential order (single-threaded solve), off with the coloured one
  On,
  Off,
};

/// Options of one contraction run. Lengths are in normalized units (bounding-box diagonal 1).
struct SimOptions {
  double pressure = DEFAULT_PRESSURE;            ///< P, normalized units
  /// R of the enclosed air (air_net_pressure): the net pressure vanishes at V/V0 = R; 0 = no air.
  double air_balance = DEFAULT_AIR_BALANCE;
  PressureModel pressure_model = PressureModel::EnergyConsistent;
  int frames = 200;                              ///< number of time steps
  double dt = 0.01;                              ///< time step (math-spec 14)
  SolverSettings solver;                         ///< pbd/xpbd, iterations (5), k_B (0.01)
  MaterialKind material = MaterialKind::Stvk;
  MaterialParams material_params;
  /// Rest-aware by default: the paper's flat-rest isometric model pushes a curved shell outward
  /// even at P = 0 (docs/design/defaults.md "Rest drift").
  BendingModel bending = BendingModel::Dihedral;
  MassModel mass = MassModel::AreaLumped;
  double density = 1.0;                          ///< rho_A, mass per normalized area
  /// epsilon: stop at the step whose V/V0 would fall below epsilon, with the volume projected onto
  /// epsilon V0 in that step (docs/math/volume-control.md), so the run ends on epsilon (0 = off).
  double stop_volume_ratio = 0.0;
  /// R: drive V/V0 to R and hold it there with a global volume constraint
  /// (docs/math/volume-control.md); 0 = off.
  double target_volume = 0.0;
  /// Frames over which the constraint's target goes from V0 to R V0 (smoothstep ramp).
  int target_ramp_frames = DEFAULT_TARGET_RAMP_FRAMES;
  /// Keyframed target V/V0 (--target-volume "0:1, 60:0.5, 120:0.85"); when not empty it is the
  /// target instead of the ramp to target_volume, and target_volume is its last key's value
  /// (docs/design/keyframes.md).
  Schedule target_volume_schedule;
  /// Keyframed pressure (-p "0:4, 100:0"); when not empty it is P at each frame, and pressure is
  /// its largest key value (what the checks of "is there a compressing pressure" read).
  Schedule pressure_schedule;
  double damping = DEFAULT_DAMPING;              ///< fraction of velocity removed per step, [0, 1)
  AnisotropyOptions anisotropy;                  ///< fibres, kappa_A (solver.aniso = model)
  InwardTerm inward_term = InwardTerm::Volume;
  /// How much the regions shrink, in [0, 1]: the local contraction's strength (dimple_rest_volume
  /// for InwardTerm::Volume, region_pressure for InwardTerm::Force).
  double region_shrink = DEFAULT_REGION_SHRINK;
  DimpleShape dimple_shape = DimpleShape::Mirror;  ///< InwardTerm::Volume's dimple (--dimple)
  /// Continuous collision detection and response (paper section 4). On by default: users expect
  /// a result that never passes through itself (design/self-collision.md).
  bool collisions = true;
  CollisionOptions collision;                    ///< delta, rounds, broad-phase method
  /// --delta auto: the plan (plan_simulation) sets collision.delta to auto_contact_distance of
  /// the normalized rest mesh, capped at the collision.delta given (sim/contact_distance.hpp).
  bool auto_delta = false;
  /// Sets collision.speculative when the options are resolved (the value given there is ignored).
  SpeculativeBroadPhase speculative_broad_phase = SpeculativeBroadPhase::Auto;
  ValidateMode validate = ValidateMode::Off;
  /// Fill FrameMetrics::energies after every step. Costs a pass over every constraint (a
  /// noticeable share of a default run; lab/history.md), so a caller that does not log them
  /// (the CLI
  /// without --log) turns it off; Simulator::energies() still computes them on demand.
  bool frame_energies = true;
};

/// A step that moves a vertex farther than this (normalized units: the mesh's bounding-box
/// diagonal is 1) is a blow-up: the run stops with SimulationError (exit code 3).
inline constexpr double BLOWUP_DISPLACEMENT = 1.0;

}  // namespace shellcontract
