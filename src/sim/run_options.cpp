#include "shellcontract/sim/run_options.hpp"

#include "shellcontract/core/error.hpp"
#include "shellcontract/material/material.hpp"

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

void resolve_run_options(RunOptions& r) {
  if (r.young.has_value() != r.thickness.has_value())
    throw UsageError("--young needs --thickness (and the other way round)");
  if (r.young) {
    const MaterialParams lame = membrane_lame_from_young(*r.young, r.poisson, *r.thickness);
    r.sim.material_params.mu = lame.mu;
    r.sim.material_params.lambda = lame.lambda;
  }
  if (r.sim.solver.kind == SolverKind::Pbd && r.sim.solver.k_bending > 1.0)
    throw UsageError("--k-b: in pbd mode k_B is a correction multiplier and must be in [0, 1]");
  if (r.sim.target_volume > 0.0 && r.sim.stop_volume_ratio > 0.0)
    throw UsageError(
        "--target-volume and --stop-volume-ratio exclude each other (the target holds the "
        "volume, the stop ends the run when it is reached)");
  resolve_sim_options(r.sim);
}

}  // namespace shellcontract
