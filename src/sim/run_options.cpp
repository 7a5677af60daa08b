#include "shellcontract/sim/run_options.hpp"

#include <utility>

#include "shellcontract/core/error.hpp"
#include "shellcontract/material/material.hpp"
#include "shellcontract/material/registry.hpp"
#include "shellcontract/sim/option_table.hpp"

namespace shellcontract {

void resolve_sim_options(SimOptions& o) {
  o.solver.dt = o.dt;
  o.collision.threads = o.solver.threads;
  o.anisotropy.mu_aniso = o.material_params.mu_aniso;
  o.solver.k_a_in_projection = o.inward_term == InwardTerm::Projection;
  // The speculative broad phase uses the core a single-threaded solve leaves idle (config.hpp).
  o.collision.speculative = o.speculative_broad_phase == SpeculativeBroadPhase::On ||
                            (o.speculative_broad_phase == SpeculativeBroadPhase::Auto &&
                             o.solver.order == ConstraintOrder::Sequential);
}

ConstraintOrder order_for(OrderChoice choice) {
  return choice == OrderChoice::Sequential ? ConstraintOrder::Sequential : ConstraintOrder::Coloured;
}

namespace {

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
  if (r.young && r.thickness) {
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

}  // namespace

void resolve_run_options(RunOptions& r) {
  resolve_default_run(r);
  if (r.young.has_value() != r.thickness.has_value())
    throw UsageError("--young needs --thickness (and the other way round)");
  if (r.young) {
    const MaterialParams lame = membrane_lame_from_young(*r.young, r.poisson, *r.thickness);
    r.sim.material_params.mu = lame.mu;
    r.sim.material_params.lambda = lame.lambda;
    // Under xpbd k_B is a stiffness, so the material gives it too: the plate's bending rigidity
    // for the dihedral energy. With it the wrinkles' size follows the thickness and is the same
    // on bear and bear x4 (lab/pages/wrinkles.md). In pbd k_B is a correction multiplier,
    // not a stiffness.
    if (r.sim.solver.kind == SolverKind::Xpbd && r.sim.bending == BendingModel::Dihedral &&
        !r.given.count("k-b"))
      r.sim.solver.k_bending = dihedral_k_bending_from_young(*r.young, r.poisson, *r.thickness);
  }
  if (r.sim.solver.kind == SolverKind::Pbd && r.sim.solver.k_bending > 1.0)
    throw UsageError("--k-b: in pbd mode k_B is a correction multiplier and must be in [0, 1]");
  // Weights are the regions: another region source beside them is a contradiction.
  if (!r.region_weight_file.empty() || !r.vertex_weights.empty()) {
    if (r.regions != RegionSource::Weights && r.given.count("regions"))
      throw UsageError(
          "--region-weights and --regions exclude each other (the weighted faces are the regions)");
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
  if (r.sim.target_volume > 0.0 && r.sim.stop_volume_ratio > 0.0)
    throw UsageError(
        "--target-volume and --stop-volume-ratio exclude each other (the target holds the "
        "volume, the stop ends the run when it is reached)");
  resolve_sim_options(r.sim);
}

std::vector<std::string> ineffective_options(const RunOptions& r) {
  const SimOptions& s = r.sim;
  std::vector<std::string> w;
  auto check = [&](const char* name, bool no_effect, const std::string& why) {
    if (no_effect && r.given.count(name))
      w.push_back(std::string("--") + name + " has no effect: " + why);
  };
  const bool aniso = s.solver.aniso != AnisoKind::None;
  const bool regions = r.regions != RegionSource::None;
  const bool pbd = s.solver.kind == SolverKind::Pbd;
  const bool k_a_projected = aniso && pbd && s.inward_term == InwardTerm::Projection;
  check("region-max-area", r.regions != RegionSource::Auto,
        "it filters the regions of --regions auto");
  check("region-shrink", !regions || s.inward_term == InwardTerm::None || k_a_projected,
        "the local contraction acts on the regions of --regions (or --aniso) with --inward "
        "volume or force");
  check("k-a", !k_a_projected, "kappa_A acts with --aniso, --inward projection and --solver pbd");
  check("inward", !regions, "the inward term acts on the regions of --regions (or --aniso)");
  check("mu-a", aniso && pbd && s.inward_term != InwardTerm::Projection,
        "a PBD projection does not depend on the stiffness (mu_A acts with --solver xpbd, or "
        "through k_A with --inward projection)");
  for (const char* name : {"mu-a", "fiber", "inversion-aware"})
    check(name, !aniso, "no --aniso energy is chosen");
  check("fiber-target", s.solver.aniso != AnisoKind::ActiveFiber,
        "it is the active fibre's (--aniso active-fiber)");
  for (const char* name : {"c10", "c01"})
    check(name, s.material != MaterialKind::MooneyRivlin,
          "it is a Mooney-Rivlin parameter (--material mooney-rivlin)");
  for (const char* name : {"mu", "lambda"})
    check(name, s.material == MaterialKind::MooneyRivlin, "Mooney-Rivlin takes --c10 and --c01");
  check("poisson", !r.young.has_value(), "the Poisson ratio is used with --young and --thickness");
  check("k-b", s.bending == BendingModel::None, "--bending none");
  for (const char* name : {"delta", "collision-rounds", "warm-start", "speculative-broad-phase"})
    check(name, !s.collisions, "--collisions off");
  check("target-ramp",
        !(s.target_volume > 0.0) && !(regions && s.inward_term == InwardTerm::Volume),
        "it is the ramp of --target-volume and of the regions' shrink (--inward volume)");
  check("target-ramp", !s.target_volume_schedule.empty(),
        "the keys of --target-volume set its timing");
  // A key after the last frame is never reached: the run ends part way to it.
  for (const auto& [name, keys] : {std::pair<const char*, const Schedule*>{
                                       "target-volume", &s.target_volume_schedule},
                                   {"pressure", &s.pressure_schedule}})
    if (!keys->empty() && keys->last_frame() > s.frames)
      w.push_back(std::string("--") + name + ": the key at frame " +
                  std::to_string(keys->last_frame()) + " comes after the last frame (" +
                  std::to_string(s.frames) + "); the run ends on the schedule's value there, " +
                  shortest_text(keys->at(s.frames)));
  check("air-balance", s.target_volume > 0.0,
        "with --target-volume the volume constraint decides the volume");
  check("air-balance", !(s.pressure > 0.0) && !(s.target_volume > 0.0),
        "the air balances a compressing pressure, and -p is not > 0");
  if (s.stop_volume_ratio > 0.0 && s.target_volume <= 0.0 && s.air_balance > 0.0 &&
      s.stop_volume_ratio <= s.air_balance)
    w.push_back("--stop-volume-ratio " + shortest_text(s.stop_volume_ratio) +
                " is at or below the air balance " + shortest_text(s.air_balance) +
                ": the air inside stops the shell above it, so the run may stall first (lower "
                "--air-balance, 0 = no air)");
  check("pressure", s.target_volume > 0.0,
        "with --target-volume the volume constraint decides the volume (the pressure only adds "
        "momentum "
        "along its own direction, which the constraint removes)");
  return w;
}

}  // namespace shellcontract
