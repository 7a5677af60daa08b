// The run plan (run_plan.hpp, docs/design/run-plan.md): the one place where the options get
// their defaults, their derived values and their checks, and where the regions become the mesh's
// "f:region" map.
#include "sim/run_plan.hpp"

#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <utility>

#include "core/cancellation.hpp"
#include "core/progress_stage.hpp"
#include "geometry/curvature.hpp"
#include "material/registry.hpp"
#include "mesh/eigen_point_map.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/material.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/regions.hpp"
#include "sim/contact_distance.hpp"
#include "sim/option_ranges.hpp"
#include "sim/region_weights.hpp"
#include "sim/volume_warnings.hpp"

namespace shellcontract {
namespace {

/// The largest stiffness (mu, lambda, C10, C01, mu_A, k_B) a run accepts, in normalized units
/// (the mesh scaled to a unit diagonal, where the default shell has mu about 0.77): far beyond
/// any material, and far enough below the largest double that the energies and the XPBD
/// compliances, which square and multiply stiffnesses, stay finite. Above about 1e155 a run
/// went on as if the membrane had no stiffness at all. kappa_A is held to it too: k_A is
/// kappa_A x mu_A x sqrt(face area), and an unbounded kappa_A times mu_A overflowed to inf.
constexpr double MAX_STIFFNESS = 1e100;

/// A field's value in the option table's range (option_ranges.hpp), refused as the table
/// refuses the same value given as text: the same range, the same message.
void require(const char* field, double value, const option_ranges::Interval& range) {
  if (!range.contains(value))
    throw UsageError(std::string("`") + field + "`: '" + shortest_text(value) + "' is not " +
                     range.text);
}

void require(const char* field, long value, const option_ranges::IntegerRange& range) {
  if (value < range.lo || value > range.hi)
    throw UsageError(std::string("`") + field + "`: '" + std::to_string(value) + "' is not " +
                     range.text());
}

/// Every range and every rule between the simulation options, in one list (the option table
/// refuses a bad value of one option as it is parsed; this also holds a caller that writes the
/// fields). The ranges are the table's own (option_ranges.hpp), checked first so that a value is
/// refused as its text would be, but for three bounds that refuse a user's typo, not a value the
/// run cannot take: the frames' upper bound (bench error's substeps multiply the frames of a run
/// that the table bounded), the iterations' (bench error's pbd reference check runs twice
/// --pbd-ref-iterations, which is held to the table's bound) and the pressure's (any finite one).
void check_sim_options_impl(const SimOptions& o) {
  namespace ranges = option_ranges;
  auto fail = [](const std::string& what) { throw UsageError(what); };
  const MaterialParams& m = o.material_params;
  // In the option table's order.
  require("pressure", o.pressure, ranges::any_finite());
  require("air_balance", o.air_balance, ranges::air_balance());
  if (o.target_volume_schedule.empty()) {
    require("target_volume", o.target_volume, ranges::target_volume());
  } else {
    for (const double key :
         {o.target_volume_schedule.min_value(), o.target_volume_schedule.max_value()})
      require("target_volume", key, ranges::keyed_target_volume());
  }
  if (!o.pressure_schedule.empty())
    for (const double key : {o.pressure_schedule.min_value(), o.pressure_schedule.max_value()})
      require("pressure", key, ranges::any_finite());
  require("target_ramp", o.target_ramp_frames, ranges::TARGET_RAMP);
  require("stop_volume_ratio", o.stop_volume_ratio, ranges::stop_volume_ratio());
  if (o.frames < ranges::FRAMES.lo)  // its lower bound alone (above)
    fail("`frames`: '" + std::to_string(o.frames) +
         "' is not an integer >= " + std::to_string(ranges::FRAMES.lo));
  require("dt", o.dt, ranges::dt());
  if (o.solver.iterations < ranges::ITERATIONS.lo)  // its lower bound alone (above)
    fail("`iterations`: '" + std::to_string(o.solver.iterations) +
         "' is not an integer >= " + std::to_string(ranges::ITERATIONS.lo));
  require("threads", o.solver.threads, ranges::THREADS);
  require("damping", o.damping, ranges::damping());
  require("mu", m.mu, ranges::mu());
  require("lambda", m.lambda, ranges::lambda());
  require("c10", m.c10, ranges::c10());
  require("c01", m.c01, ranges::c01());
  require("k_b", o.solver.k_bending, ranges::k_b());
  require("density", o.density, ranges::density());
  require("k_a", o.anisotropy.kappa_a, ranges::k_a());
  require("region_shrink", o.region_shrink, ranges::region_shrink());
  require("mu_a", m.mu_aniso, ranges::mu_a());
  require("fiber_target", m.fiber_target, ranges::fiber_target());
  require("delta", o.collision.delta, ranges::delta());
  require("collision_rounds", o.collision.rounds, ranges::COLLISION_ROUNDS);
  // After the table's ranges, so that a value the table refuses (mu = -1e101: not > 0) gets the
  // table's message, as the same value given as text does; the bound holds what they allow.
  for (const auto& [name, value] : {std::pair<const char*, double>{"mu", m.mu},
                                    {"lambda", m.lambda},
                                    {"c10", m.c10},
                                    {"c01", m.c01},
                                    {"mu_a", m.mu_aniso},
                                    {"k_b", o.solver.k_bending},
                                    {"k_a", o.anisotropy.kappa_a}})
    if (std::abs(value) > MAX_STIFFNESS)
      fail(std::string("`") + name + "` must be at most " + shortest_text(MAX_STIFFNESS) +
           (value < 0.0 ? " in size" : ""));
  // Not an option of the table: a caller's own margin.
  if (!(o.collision.region_margin >= 0.0) || !std::isfinite(o.collision.region_margin))
    fail("collision.region_margin must be >= 0");
  // The rules between options.
  // The membrane energy mu tr E^2 + lambda/2 tr^2 E (and the corotated and linear ones, the same
  // form in their strain) is positive definite for mu > 0 and mu + lambda > 0: lambda / mu in
  // (-1, inf), which holds the plane-stress lambda / mu = 2 nu / (1 - nu) of every Poisson ratio
  // in (-1, 1/2]. At or below -mu a uniform stretch lowers the energy and the constraint
  // C = sqrt(2 E) has no real value.
  if (!(m.mu + m.lambda > 0.0))
    fail(
        "`lambda` must be greater than -mu (mu + lambda > 0, as a Poisson ratio above -1 gives); "
        "got mu " +
        shortest_text(m.mu) + ", lambda " + shortest_text(m.lambda));
  if (o.solver.kind == SolverKind::Pbd && o.solver.k_bending > 1.0)
    fail("`k_b`: in pbd mode k_B is a correction multiplier and must be in [0, 1]");
  if (!o.target_volume_schedule.empty() && o.target_volume != o.target_volume_schedule.last_value())
    fail("`target_volume` must be the last key's value of its schedule");
  if (!o.pressure_schedule.empty() && o.pressure != o.pressure_schedule.max_value())
    fail("`pressure` must be the largest key value of its schedule");
  if (o.target_volume > 0.0 && o.stop_volume_ratio > 0.0)
    fail(
        "`target_volume` and `stop_volume_ratio` exclude each other (the target holds the "
        "volume, the stop ends the run when it is reached)");
}

/// The paper's settings where the caller left the default run's (RunOptions): under pbd the
/// membrane is mu and lambda and the damping DEFAULT_DAMPING; chosen mu or lambda are the
/// membrane. Idempotent, like the rest of resolve_run_options.
void resolve_default_run(RunOptions& r) {
  const auto chosen = [&r](const char* name, bool changed) {
    return r.given.count(name) || changed;
  };
  const MaterialParams paper;
  const bool pbd = r.sim.solver.kind == SolverKind::Pbd;
  const bool shell_chosen = r.given.count("young") || r.given.count("thickness");
  // mu and lambda that the shell material gave (an earlier resolve) are not chosen.
  const MaterialParams& m = r.sim.material_params;
  bool from_shell = false;
  // Values out of range are refused next, by check_table_ranges, naming the option; here they
  // only mean that mu and lambda did not come from them.
  const auto in_range = [](double x) { return x > 0.0 && std::isfinite(x); };
  if (r.young && r.thickness && in_range(*r.young) && in_range(*r.thickness) && r.poisson > -1.0 &&
      r.poisson < 1.0) {
    const MaterialParams shell = membrane_lame_from_young(*r.young, r.poisson, *r.thickness);
    from_shell = m.mu == shell.mu && m.lambda == shell.lambda;
  }
  const bool lame_chosen = chosen("mu", !from_shell && m.mu != paper.mu) ||
                           chosen("lambda", !from_shell && m.lambda != paper.lambda);
  if (!shell_chosen && (pbd || lame_chosen || r.sim.material == MaterialKind::MooneyRivlin)) {
    r.young.reset();
    r.thickness.reset();
  }
  if (pbd && !chosen("damping", r.sim.damping != DEFAULT_XPBD_DAMPING))
    r.sim.damping = DEFAULT_DAMPING;
}

/// Holds a caller that writes the fields (C++) to the ranges the option table holds the CLI and
/// Python to: each option's value, as the table prints it, must parse back through the table.
/// check_sim_options alone let through values the table refuses (mu = -1 or NaN, density = inf,
/// delta = 0.5, a zero fibre direction, keyframes out of order), and such a run went on to a
/// result that ignored them or made no sense.
/// Called after resolve_default_run: mu and lambda that the shell material (young, thickness)
/// is about to set are not checked, since a resolved run's lambda is negative for a negative
/// Poisson ratio, which the table accepts.
void check_table_ranges(const RunOptions& r) {
  const bool lame_from_shell = r.young.has_value() && r.thickness.has_value();
  for (const OptionSpec& o : run_option_table()) {
    if (lame_from_shell && (o.name == "mu" || o.name == "lambda")) continue;
    const std::string text = o.get(r);
    // "" is an unset optional value, or weights or points not given; but for `regions` it is
    // RegionSource::File without a file, which the table refuses.
    if (text.empty() && o.name != "regions") continue;
    RunOptions scratch;
    o.set(scratch, text);  // UsageError naming the option by its field, as for the CLI's text
  }
}

}  // namespace

void check_sim_options(const SimOptions& o) { check_sim_options_impl(o); }

void resolve_sim_options(SimOptions& o) {
  o.solver.dt = o.dt;
  o.collision.threads = o.solver.threads;
  o.anisotropy.mu_aniso = o.material_params.mu_aniso;
  o.solver.k_a_in_projection = o.inward_term == InwardTerm::Projection;
  // The speculative broad phase uses the core a single-threaded solve leaves idle (config.hpp).
  o.collision.speculative = o.speculative_broad_phase == SpeculativeBroadPhase::On ||
                            (o.speculative_broad_phase == SpeculativeBroadPhase::Auto &&
                             o.solver.order == ConstraintOrder::Sequential);
  // The choice made: the summary, a checkpoint and a sweep's job id record what ran, so that
  // "auto" and the value it chose are one run (docs/cli.md, --summary: resolved values).
  o.speculative_broad_phase =
      o.collision.speculative ? SpeculativeBroadPhase::On : SpeculativeBroadPhase::Off;
  check_sim_options(o);
}

void resolve_run_options(RunOptions& r) {
  r.sim.solver.order = order_for(r.order);
  r.order = r.sim.solver.order == ConstraintOrder::Sequential ? OrderChoice::Sequential
                                                              : OrderChoice::Coloured;
  resolve_default_run(r);
  check_table_ranges(r);
  if (r.young.has_value() != r.thickness.has_value())
    throw UsageError("`young` needs `thickness` (and the other way round)");
  if (r.young) {
    const MaterialParams lame = membrane_lame_from_young(*r.young, r.poisson, *r.thickness);
    const double bending = dihedral_k_bending_from_young(*r.young, r.poisson, *r.thickness);
    if (!(std::max({lame.mu, lame.lambda, bending}) <= MAX_STIFFNESS))
      throw UsageError("`young` " + shortest_text(*r.young) + " and `thickness` " +
                       shortest_text(*r.thickness) + " give the stiffnesses mu " +
                       shortest_text(lame.mu) + ", lambda " + shortest_text(lame.lambda) +
                       " and k_B " + shortest_text(bending) + "; each must be at most " +
                       shortest_text(MAX_STIFFNESS));
    r.sim.material_params.mu = lame.mu;
    r.sim.material_params.lambda = lame.lambda;
    // Under xpbd k_B is a stiffness, so the material gives it too: the plate's bending rigidity
    // for the dihedral energy. With it the wrinkles' size follows the thickness and is the same
    // on bear and bear x4 (lab/pages/wrinkles.md). In pbd k_B is a correction multiplier,
    // not a stiffness.
    if (r.sim.solver.kind == SolverKind::Xpbd && r.sim.bending == BendingModel::Dihedral &&
        !r.given.count("k_b"))
      r.sim.solver.k_bending = bending;
  }
  // Points are the regions too: the caps at them, selected like --regions auto's.
  if (!r.region_points.empty()) {
    if (r.given.count("regions") || !r.region_weight_file.empty() || !r.vertex_weights.empty())
      throw UsageError(
          "`region_at` excludes `regions` and `region_weights` (the caps at the points are the regions)");
    r.regions = RegionSource::Auto;
  }
  // Weights are the regions: another region source beside them is a contradiction.
  if (!r.region_weight_file.empty() || !r.vertex_weights.empty()) {
    if (r.regions != RegionSource::Weights && r.given.count("regions"))
      throw UsageError(
          "`region_weights` and `regions` exclude each other (the weighted faces are the regions)");
    r.regions = RegionSource::Weights;
  }
  // An anisotropic energy acts on regions, so choosing one without saying which selects them
  // by curvature (the behaviour before regions switched the local contraction on by themselves).
  const bool implied = r.regions == RegionSource::None && !r.given.count("regions");
  if (implied && r.sim.solver.aniso != AnisoKind::None) r.regions = RegionSource::Auto;
  // --measure-regions alone selects the regions only to report how far they sink in a run that
  // does not contract them: the baseline of the local contraction's measurements.
  if (implied && r.measure_regions && r.sim.solver.aniso == AnisoKind::None) {
    r.regions = RegionSource::Auto;
    r.sim.inward_term = InwardTerm::None;
  }
  // The finder drops regions below its smallest share of the surface: a bound under it keeps
  // none (check_region_options' words would name the `regions` command's options instead).
  const double smallest = RegionOptions{}.min_area_fraction;
  if (r.regions == RegionSource::Auto && r.region_max_area < smallest)
    throw UsageError("`region_max_area` " + shortest_text(r.region_max_area) +
                     " is below the smallest region `regions` auto keeps, " +
                     shortest_text(smallest) +
                     " of the surface (smaller ones are noise): no region could be kept");
  // RegionSource::Weights comes with `region_weights` (the CLI's file, Python's array); a caller
  // that sets it alone would have the run look for a weight file with no name.
  if (r.regions == RegionSource::Weights && r.region_weight_file.empty() &&
      r.vertex_weights.empty())
    throw UsageError(
        "`regions` from weights needs `region_weights`: a file of one weight per vertex, or the "
        "weights");
  resolve_sim_options(r.sim);  // and the checks of every simulation option
}

std::size_t mark_run_regions(Mesh& mesh, const RunOptions& options,
                             std::vector<std::string>* warnings) {
  switch (options.regions) {
    case RegionSource::File: {
      const RegionFile file = read_region_file_with_strengths(options.region_file, mesh.number_of_faces());
      store_regions(mesh, face_ids_from_regions(file.regions, mesh.number_of_faces()));
      store_region_strengths(mesh, file.regions, file.strength);  // a "S:" column, if any
      return file.regions.size();
    }
    case RegionSource::Auto: {
      RegionOptions o;
      o.max_area_fraction = options.region_max_area;
      if (!options.region_points.empty()) {
        const Positions x = positions_from_mesh(mesh);
        RegionReport report;
        const std::vector<int> ids = select_regions_at(mesh, x, options.region_points, o, &report);
        store_curvature(mesh, compute_curvature(mesh, x));  // as mark_spherical_regions does
        store_regions(mesh, ids);
        if (warnings)  // points far from the surface
          for (std::string& w : report.warnings) warnings->push_back(std::move(w));
        return options.region_points.size();
      }
      return mark_spherical_regions(mesh, positions_from_mesh(mesh), o);
    }
    case RegionSource::Weights: {
      // One weight per input vertex (a welded mesh's copies included: mesh_io.hpp, "Seams").
      if (!options.vertex_weights.empty()) {
        check_vertex_weights(options.vertex_weights, input_vertex_count(mesh), "region_weights");
        return mark_weighted_regions(mesh, options.vertex_weights);
      }
      return mark_weighted_regions(
          mesh, read_vertex_weights(options.region_weight_file, input_vertex_count(mesh)));
    }
    case RegionSource::None:
      break;
  }
  store_regions(mesh, std::vector<int>(mesh.number_of_faces(), -1));
  return 0;
}

SimPlan plan_simulation(Mesh mesh, SimOptions options) {
  resolve_sim_options(options);
  if (mesh.has_garbage()) throw UsageError("Simulator: the input mesh has garbage");
  SimPlan plan;
  plan.normalization = compute_normalization(positions_from_mesh(mesh));
  const Positions x = normalize(positions_from_mesh(mesh), plan.normalization);
  for (VertexIndex v : mesh.vertices()) {
    const auto r = x.row(v.idx());
    mesh.point(v) = Point3(r(0), r(1), r(2));
  }
  if (options.collisions) {
    progress_stage("choosing the contact distance");
    ContactDistanceChoice delta = choose_contact_distance(mesh, options);
    options.collision.delta = delta.delta;
    plan.warnings = std::move(delta.warnings);
    plan.held_at_rest = delta.held_at_rest;
    cancellation_point();
  }
  plan.mesh = std::move(mesh);
  plan.options = std::move(options);
  return plan;
}

RunPlan plan_run(const Mesh& mesh, const RunOptions& options) {
  RunPlan plan;
  plan.options = options;
  RunOptions& o = plan.options;
  resolve_run_options(o);
  // Options refused before a cancel is heard; the regions, the longest part on a large mesh,
  // check it between their stages.
  cancellation_point();
  const auto regions_start = std::chrono::steady_clock::now();
  // The run's regions travel as the f:region map of its copy of the mesh (one owner: the run
  // options say where they come from).
  Mesh marked = mesh;
  switch (o.regions) {  // the longest stage of the preparation on a large mesh
    case RegionSource::Auto:
      progress_stage(o.region_points.empty() ? "selecting the regions"
                                             : "growing the regions at the given points");
      break;
    case RegionSource::File:
      progress_stage("reading the regions file");
      break;
    case RegionSource::Weights:
      progress_stage("reading the region weights");
      break;
    case RegionSource::None:
      break;
  }
  plan.regions = mark_run_regions(marked, o, &plan.warnings);
  cancellation_point();
  plan.regions_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - regions_start).count();
  const SimOptions& s = o.sim;
  if (s.solver.aniso != AnisoKind::None && plan.regions == 0)
    plan.warnings.push_back(
        "`aniso` " + to_string(s.solver.aniso) +
        " has no effect: no region was found (or given), so no face gets the anisotropic energy");
  else if (o.regions == RegionSource::File && plan.regions == 0 && !o.measure_regions)
    plan.warnings.push_back("`regions` " + o.region_file +
                            ": the file lists no region (only blank or comment lines): the local "
                            "contraction has no effect");
  else if (o.regions == RegionSource::File && !o.measure_regions && [&] {
             // Every line's strength 0 ("0: 12 13 14"): regions that sink not at all.
             const std::vector<double> w = stored_region_weights(marked);
             return !w.empty() &&
                    std::all_of(w.begin(), w.end(), [](double s) { return s == 0.0; });
           }())
    plan.warnings.push_back("`regions` " + o.region_file +
                            ": every region's strength is 0: the local contraction has no effect");
  else if (o.regions == RegionSource::Weights && plan.regions == 0 && !o.measure_regions)
    plan.warnings.push_back("`region_weights`" +
                            (o.region_weight_file.empty() ? std::string() : " " + o.region_weight_file) +
                            ": every weight is 0, so no face is in a region: the local contraction "
                            "has no effect");
  else if (o.regions != RegionSource::None && plan.regions == 0 && !o.measure_regions)
    plan.warnings.push_back("`regions` auto found no region: the local contraction has no effect");
  // The air, the target and the stop ratio see the enclosed volume of the whole mesh: separate
  // shells share them, and one may give volume to another (a small ball re-inflating while a
  // large one takes the target). Said, since each component is otherwise its own shell.
  std::vector<std::string> whole;
  if (s.target_volume > 0.0) whole.push_back("the target volume");
  if (s.stop_volume_ratio > 0.0) whole.push_back("the stop ratio");
  if (s.air_balance > 0.0 && s.pressure != 0.0) whole.push_back("the enclosed air");
  if (!whole.empty()) {
    std::vector<std::size_t> component(mesh.number_of_faces());
    const std::size_t components = CGAL::Polygon_mesh_processing::connected_components(
        mesh, CGAL::make_property_map(component));
    std::string what = whole[0];
    for (std::size_t i = 1; i < whole.size(); ++i)
      what += (i + 1 == whole.size() ? " and " : ", ") + whole[i];
    if (components > 1)
      plan.warnings.push_back("the mesh has " + std::to_string(components) +
                              " separate components: " + what +
                              (whole.size() > 1 ? " act" : " acts") +
                              " on their total volume, so one may shrink more than asked while "
                              "another shrinks less; run them one at a time for a V/V0 each");
  }
  // Said before the run, not after every frame ran: a run that nothing drives, or a stop ratio
  // that an inflating shell never reaches. Regions contract when an inward term or an
  // anisotropic energy acts on them.
  const bool regions_act =
      plan.regions > 0 && (s.inward_term != InwardTerm::None || s.solver.aniso != AnisoKind::None);
  for (std::string& w : drive_warnings(s, regions_act)) plan.warnings.push_back(std::move(w));
  for (std::string& w : ineffective_options(o)) plan.warnings.push_back(std::move(w));
  plan.sim = plan_simulation(std::move(marked), o.sim);  // one copy of a large mesh fewer
  for (std::string& w : plan.sim.warnings) plan.warnings.push_back(std::move(w));
  plan.sim.warnings.clear();
  return plan;
}

}  // namespace shellcontract
