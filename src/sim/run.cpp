#include "shellcontract/run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/arena_threads.hpp"
#include "core/cancellation.hpp"
#include "core/decimal_text.hpp"
#include "core/plural.hpp"
#include "core/progress_stage.hpp"
#include "mesh/eigen_point_map.hpp"
#include "mesh/file_safety.hpp"
#include "shellcontract/error.hpp"
#include "sim/air_step.hpp"
#include "sim/checkpoint.hpp"
#include "sim/simulator.hpp"
#include "sim/target_goal.hpp"
#include "sim/volume_warnings.hpp"

namespace shellcontract {

const char* status_name(RunStatus status) {
  switch (status) {
    case RunStatus::Completed:
      return "ok";
    case RunStatus::TargetNotReached:
      return "target not reached";
    case RunStatus::SimulationFailed:
      return "failed";
    case RunStatus::NewIntersections:
      return "new self-intersections";
    case RunStatus::Cancelled:
      return "cancelled";
  }
  return "failed";
}

int RunResult::exit_code() const {
  switch (status) {
    case RunStatus::Completed:
      return static_cast<int>(ExitCode::Success);
    case RunStatus::TargetNotReached:
      return static_cast<int>(ExitCode::TargetNotReached);
    case RunStatus::SimulationFailed:
      return static_cast<int>(ExitCode::SimulationFailed);
    case RunStatus::NewIntersections:
      return static_cast<int>(ExitCode::NewSelfIntersections);
    case RunStatus::Cancelled:
      return static_cast<int>(ExitCode::Cancelled);
  }
  return static_cast<int>(ExitCode::SimulationFailed);
}

void ObserverList::warning(const std::string& text) {
  for (RunObserver* o : observers_) o->warning(text);
}
void ObserverList::stage(const std::string& what) {
  for (RunObserver* o : observers_) o->stage(what);
}
void ObserverList::started(const FrameView& view) {
  for (RunObserver* o : observers_) o->started(view);
}
void ObserverList::frame(const FrameView& view, const FrameMetrics& m) {
  for (RunObserver* o : observers_) o->frame(view, m);
}
bool ObserverList::cancelled() {
  bool any = false;
  for (RunObserver* o : observers_) any = o->cancelled() || any;
  return any;
}
void ObserverList::finished(const FrameView& view, const RunResult& r) {
  for (RunObserver* o : observers_) o->finished(view, r);
}

namespace {

/// Ends the run on std::bad_alloc (`when`: where it ran out), keeping the state as it is: the
/// message says how large the mesh is and, from the last step, how many candidate pairs the
/// collision step held, which is what grows with a finer mesh and a faster motion.
void fail_out_of_memory(RunResult& r, const std::string& when, const Mesh& mesh,
                        std::int64_t last_pairs) {
  std::string text =
      "out of memory " + when + " (" + std::to_string(mesh.number_of_faces()) + " faces";
  if (last_pairs > 0)
    text += "; the last completed step held " + std::to_string(last_pairs) +
            " candidate contact pairs, about 100 bytes each";
  text +=
      "): a coarser mesh, or a contact distance in proportion to the edges (delta auto), "
      "needs less memory";
  // What the run had found before (new self-intersections) stays in the message.
  if (r.status != RunStatus::Completed) text += "; before that: " + r.message;
  r.status = RunStatus::SimulationFailed;
  r.message = text;
}

/// What the message of a run cancelled with `validate` end adds.
constexpr const char* SKIPPED_VALIDATION =
    "; not checked for self-intersections (the check at the end is skipped for a cancelled run)";

/// `r` as the result of a run cancelled before its first step (while its regions were selected or
/// its Simulator built): nothing ran, its positions are the input's (the caller's to set), and
/// neither started() nor finished() is called (there is no frame to show). `interrupted`: by the
/// checkpointer's stop() (the CLI's signal), else by the observer's cancelled().
void cancelled_before_first_step(RunResult& r, bool interrupted,
                                 const RunCheckpointer* checkpointer) {
  r.status = RunStatus::Cancelled;
  r.message = std::string(interrupted ? "interrupted" : "cancelled") +
              " before the first step, while preparing the run (regions, rest state, contacts)";
  if (const Checkpoint* c = checkpointer ? checkpointer->resume_from() : nullptr) {
    r.first_frame = r.frames_run = checkpoint_frame(*c);
    r.message += "; the checkpoint it resumed from is as it was";
  }
}

/// What the preparation's cancellation points ask (cancellation.hpp): the observer, and the
/// checkpointer's stop() as the frame loop does; `interrupted` says which answered.
std::function<bool()> preparation_cancelled(RunObserver& obs, RunCheckpointer* checkpointer,
                                            bool& interrupted) {
  return [&obs, checkpointer, &interrupted] {
    interrupted = checkpointer && checkpointer->stop();
    return interrupted || obs.cancelled();
  };
}

/// The stages the preparation names (core/progress_stage.hpp), told to the observer.
ProgressStageScope observer_stages(RunObserver& obs) {
  return ProgressStageScope([&obs](const std::string& what) { obs.stage(what); });
}

/// Tells the observer and keeps the warning for the summary.
void warn(RunResult& r, RunObserver& o, const std::string& text) {
  r.warnings.push_back(text);
  o.warning(text);
}

/// run_contraction of a plan, in the run's leased arena.
RunResult run_planned(RunPlan plan, RunObserver* observer, RunCheckpointer* checkpointer,
                      const ArenaLease& lease);

}  // namespace

RunResult run_contraction(const Mesh& mesh, const RunOptions& options, RunObserver* observer,
                          RunCheckpointer* checkpointer) {
  // The Simulator's restore checks only the state's sizes: a checkpoint of another mesh with as
  // many vertices, or of other options, would be continued silently into neither run's result.
  if (const Checkpoint* c = checkpointer ? checkpointer->resume_from() : nullptr)
    check_checkpoint_fits(*c, mesh, options);
  RunObserver none;
  bool interrupted = false;
  std::optional<RunPlan> plan;
  // The run's own arena for its planning, its Simulator and its steps (core/arena_threads.hpp):
  // leased by this run alone, so execute() runs the functor, and with it the observer's stage()
  // and cancelled(), on this thread, the caller's.
  const ArenaLease lease(options.sim.solver.threads);
  try {
    // In the run's arena, as its steps: outside it the planning's parallel work (the regions,
    // the contact distance's broad phase) took TBB's default, a thread per core of the affinity,
    // whatever `threads` or a CPU quota said (core/arena_threads.hpp).
    lease.arena().execute([&] {
      const RunArenaScope in_run(lease);
      const CancellationScope scope(
          preparation_cancelled(observer ? *observer : none, checkpointer, interrupted));
      const ProgressStageScope stages = observer_stages(observer ? *observer : none);
      plan.emplace(plan_run(mesh, options));
    });
  } catch (const PreparationCancelled&) {
    RunResult r;
    cancelled_before_first_step(r, interrupted, checkpointer);
    r.positions = positions_from_mesh(mesh);
    return r;
  }
  return run_planned(std::move(*plan), observer, checkpointer, lease);
}

RunResult run_contraction(RunPlan plan, RunObserver* observer, RunCheckpointer* checkpointer) {
  const ArenaLease lease(plan.sim.options.solver.threads);
  return run_planned(std::move(plan), observer, checkpointer, lease);
}

namespace {

RunResult run_planned(RunPlan plan, RunObserver* observer, RunCheckpointer* checkpointer,
                      const ArenaLease& lease) {
  RunObserver none;
  RunObserver& obs = observer ? *observer : none;
  RunResult r;
  r.order = plan.sim.options.solver.order;
  r.regions = plan.regions;
  r.regions_seconds = plan.regions_seconds;
  for (const std::string& w : plan.warnings) warn(r, obs, w);
  const bool held_at_rest = plan.sim.held_at_rest;
  using Clock = std::chrono::steady_clock;
  const auto prepare_start = Clock::now();
  // The result's storage, taken before the first step (see the end), holds the input's positions
  // meanwhile: a run cancelled now returns them (the plan's mesh goes into the Simulator).
  denormalize_into(positions_from_mesh(plan.sim.mesh), plan.sim.normalization, r.positions);
  std::optional<Simulator> prepared;
  bool interrupted = false;
  try {
    // In the run's arena (see above): the construction's broad phase and rest pairs. The
    // Simulator made in its scope shares the lease with its solver and collision Workers.
    lease.arena().execute([&] {
      const RunArenaScope in_run(lease);
      const CancellationScope scope(preparation_cancelled(obs, checkpointer, interrupted));
      const ProgressStageScope stages = observer_stages(obs);
      cancellation_point();
      prepared.emplace(std::move(plan.sim));  // one copy of a large mesh fewer (bear x16: 26 MB)
    });
  } catch (const PreparationCancelled&) {
    cancelled_before_first_step(r, interrupted, checkpointer);
    return r;
  }
  Simulator& sim = *prepared;
  r.prepare_seconds = std::chrono::duration<double>(Clock::now() - prepare_start).count();
  const SimOptions& s = sim.options();
  const Mesh& mesh = sim.rest_mesh();  // for the size in an out-of-memory message
  if (sim.regions_without_cap() > 0)
    warn(r, obs,
         std::to_string(sim.regions_without_cap()) + " of " + std::to_string(r.regions) +
             " regions are flat or dented at rest: the local contraction (`inward` volume) "
             "shrinks a region's cap and leaves those alone");
  const RestStateReport& rest = sim.rest_report();
  if (rest.degenerate_faces > 0)
    warn(r, obs,
         std::to_string(rest.degenerate_faces) + " degenerate faces carry no membrane energy; " +
             std::to_string(rest.inactive_hinges) + " hinges touching them are inactive");
  // The masses the pressure needed, and the air's volume mode with them (air_step.hpp).
  for (const std::string& note :
       {mass_scaling_warning(sim.mass_scaling(), mesh.number_of_vertices(), s.dt),
        air_step_warning(air_step(sim.rest_positions(), sim.faces(), sim.inv_masses(), s), s)})
    if (!note.empty()) warn(r, obs, note);
  // math-spec 11: harmless under pbd, whose step does not see the stiffness.
  if (rest.sliver_faces > 0 && s.solver.kind == SolverKind::Xpbd)
    warn(r, obs,
         counted(rest.sliver_faces, "face has", "faces have") +
             " a rest angle below 1 degree (slivers): under the xpbd solver their membrane acts "
             "stiffer than its material; remeshing them away avoids it");
  // The cotangent weights belong to the isometric bending; the dihedral model does not use them.
  if (rest.clamped_cotangents > 0 && s.bending == BendingModel::Isometric)
    warn(r, obs,
         std::to_string(rest.clamped_cotangents) +
             " rest angles below 1 or above 179 degrees: their bending cotangents were clamped "
             "to +-cot(1 degree)");
  const bool has_target = s.target_volume > 0.0;
  const bool has_stop = s.stop_volume_ratio > 0.0;
  // A schedule's goal is its value at the last frame, from the frame it settles there on: before
  // that a later key still changes it.
  const Schedule& keys = s.target_volume_schedule;
  const int settled = schedule_settles_at(keys, s.frames);
  // A stop ratio's goal is fixed, but keys of the pressure that drives toward it change the load.
  const int stall_from = has_target ? settled : schedule_settles_at(s.pressure_schedule, s.frames);
  std::vector<double> history{1.0};  // V/V0 after each frame, frame 0 = the rest state
  std::string stalled;
  std::int64_t last_pairs = 0;  // the last step's candidate pairs, for an out-of-memory message
  // A resumed run: the Simulator and this loop continue where the checkpoint's run stopped.
  if (const Checkpoint* c = checkpointer ? checkpointer->resume_from() : nullptr) {
    try {
      sim.restore(c->sim);
    } catch (const InputError& e) {
      // The file, where it came from one: what the mesh refuses is the file's problem too.
      if (c->path.empty()) throw;
      throw InputError("checkpoint " + printable(c->path) + ": " + e.what());
    }
    const RunProgress& p = c->progress;
    history = p.history;
    r.min_volume_ratio = p.min_volume_ratio;
    r.totals = p.totals;
    r.new_intersections = p.new_intersections;
    r.status = p.status;
    r.message = p.message;
    r.frame_target_reached = p.frame_target_reached;
    last_pairs = p.last_pairs;
  }
  const FrameView view(sim);
  obs.started(view);
  bool cancelled = false;  // by the observer or the checkpointer

  r.first_frame = sim.frame();
  const auto start = std::chrono::steady_clock::now();
  r.positions.resize(sim.positions().rows(), 3);  // the result's storage, see the end
  const ProgressStageScope stages = observer_stages(obs);  // the last step's check (`validate` end)
  while (!sim.finished()) {
    FrameMetrics m;
    const int before = sim.frame();
    try {
      m = sim.step();
    } catch (const SimulationError& e) {
      r.status = RunStatus::SimulationFailed;
      r.message = e.what();
      break;
    } catch (const std::bad_alloc&) {
      // The step works on its own copy of the positions (Simulator::step) until it accepts
      // them, so the state is a whole step's; after that it only measures (energies, validation).
      // What grows during a run is the collision step's candidate pairs
      // (lab/pages/scale.md, "Beyond a million faces").
      fail_out_of_memory(r,
                         sim.frame() == before ? "at step " + std::to_string(before + 1)
                                               : "checking step " + std::to_string(sim.frame()),
                         mesh, last_pairs);
      break;
    } catch (const std::runtime_error& e) {
      // What the system refuses besides memory: a thread (TBB's pthread_create, "Resource
      // temporarily unavailable", when the address space is exhausted). The same state.
      r.status = RunStatus::SimulationFailed;
      r.message = "at step " + std::to_string(before + 1) + ": " + e.what();
      break;
    }
    last_pairs = m.collision.pairs_broad;
    r.min_volume_ratio = std::min(r.min_volume_ratio, m.volume_ratio);
    r.totals.add(m);
    if (m.new_intersections >= 0) r.new_intersections = m.new_intersections;
    if (m.new_intersections > 0 && r.status == RunStatus::Completed) {
      r.status = RunStatus::NewIntersections;
      r.message = std::to_string(m.new_intersections) +
                  " new self-intersecting face pairs at frame " + std::to_string(m.frame);
    }
    history.push_back(m.volume_ratio);
    if (has_target && r.frame_target_reached < 0 &&
        (keys.empty() ? std::abs(sim.volume_target(m.frame) - s.target_volume) < 1e-12 &&
                            target_volume_reached(m.volume_ratio, s.target_volume)
                      : m.frame >= settled &&
                            target_volume_reached(m.volume_ratio, sim.volume_target(m.frame))))
      r.frame_target_reached = m.frame;
    try {
      obs.frame(view, m);
    } catch (const std::bad_alloc&) {
      // An observer that keeps frames (the glTF exporter) grows with the run; the state is
      // complete.
      fail_out_of_memory(r, "after step " + std::to_string(m.frame) + " (in an observer)", mesh,
                         last_pairs);
      break;
    }
    // Stall: the volume no longer moves while it is still off the target (or above the stop
    // ratio); more frames would not get there. Not while a later key still changes the goal or
    // the pressure (the end warns of a target key not reached).
    if ((has_target || has_stop) && !sim.finished() && m.frame >= stall_from &&
        volume_stalled(history, history.size() - 1,
                       has_target ? sim.volume_target(m.frame) : s.stop_volume_ratio)) {
      stalled = stall_text(m.volume_ratio, m.frame);
      break;
    }
    // Before the observers' cancel: a caller that cancels on a signal (Python's Ctrl-C) saves
    // the state first.
    if (checkpointer && !sim.finished()) {
      if (checkpointer->save_due(sim.frame())) {
        const RunProgress progress{history,      r.min_volume_ratio, r.totals,
                                   r.new_intersections, r.status, r.message,
                                   r.frame_target_reached, last_pairs};
        checkpointer->save(SavedRun{sim, progress});
      }
      if (checkpointer->stop()) {
        r.status = RunStatus::Cancelled;
        r.message = "interrupted at frame " + std::to_string(m.frame);
        cancelled = true;
        break;
      }
    }
    if (obs.cancelled()) {
      if (r.status == RunStatus::Completed) {
        r.status = RunStatus::Cancelled;
        r.message = "cancelled at frame " + std::to_string(m.frame);
      }
      cancelled = true;
      break;
    }
  }
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // A run that stalled skipped the step's end-of-run validation: it runs here. A cancelled one
  // skips it too (on a large mesh it is the slowest part of the end, and whoever cancelled wants
  // the run to end now): its new_intersections stays -1, not validated, and its message says so.
  if (s.validate == ValidateMode::End && r.new_intersections < 0 && cancelled) {
    if (r.status == RunStatus::Cancelled) r.message += SKIPPED_VALIDATION;
  } else if (s.validate == ValidateMode::End && r.new_intersections < 0) {
    obs.stage("checking the result for self-intersections");
    try {
      r.new_intersections = static_cast<long>(sim.count_new_intersections());
    } catch (const std::bad_alloc&) {
      // Not validated (new_intersections stays -1); the state itself is good.
      fail_out_of_memory(r, "validating the result", mesh, last_pairs);
    }
    if (r.new_intersections > 0 && r.status == RunStatus::Completed) {
      r.status = RunStatus::NewIntersections;
      r.message =
          std::to_string(r.new_intersections) + " new self-intersecting face pairs at the end";
    }
  }

  r.frames_run = sim.frame();
  r.final_volume_ratio = sim.volume_ratio();
  if (const std::string w = inside_out_warning(r.final_volume_ratio, r.frames_run, s.collisions);
      !w.empty())
    warn(r, obs, w);
  // A shell that grew under an outside pressure, or whose volume swings from frame to frame,
  // ends with a V/V0 that the load does not explain, and the run would say nothing of it.
  bool compressed = !has_target;
  for (int n = 0; compressed && n < r.frames_run; ++n) compressed = sim.pressure_at(n) > 0.0;
  const bool scheduled = !s.target_volume_schedule.empty() || !s.pressure_schedule.empty();
  for (const std::string& w : volume_warnings(history, compressed, scheduled)) warn(r, obs, w);
  // A shell held at rest by its near pairs was told "nothing can move" and its remedy at the
  // start; the fail-safe's reverts are those pairs, and the frozen warning's remedies miss them.
  for (const auto& [name, total] : r.totals.per_step(r.frames_run))
    if (name == "failsafe_vertices_total" && !held_at_rest)
      if (const std::string w = frozen_warning(total, mesh.number_of_vertices(), r.frames_run);
          !w.empty())
        warn(r, obs, w);
  // From the history, which a checkpoint carries: a resumed run says it too.
  if (const int n = first_stall_before(history, keys, settled); n >= 0)
    warn(r, obs,
         "the target volume's keys were not followed: " + stall_text(history[n], n) +
             ", where the keys ask for " + volume_ratio_text(keys.at(n)) +
             "; the run went on, as a later key changes the target");
  if (has_stop) {
    r.target_reached = sim.stop_volume_reached();
    if (r.target_reached) r.frame_target_reached = sim.frame();
    const std::string below = stop_below_warning(r.final_volume_ratio, s.stop_volume_ratio);
    if (r.target_reached && !below.empty()) warn(r, obs, below);
  } else if (has_target) {
    // A schedule's goal is its value at the last frame run (a key after it is never reached).
    const double goal =
        s.target_volume_schedule.empty() ? s.target_volume : sim.volume_target(sim.frame());
    r.target_reached = target_volume_reached(r.final_volume_ratio, goal);
    // A run that ended before its schedule settled (cancelled, failed) arrived at its last frame.
    if (r.target_reached && r.frame_target_reached < 0 && !keys.empty())
      r.frame_target_reached = sim.frame();
  }
  if (!r.target_reached && r.status == RunStatus::Completed) {
    r.status = RunStatus::TargetNotReached;
    const std::string what = has_target ? "target volume " : "stop volume ratio ";
    const double goal = !has_target                          ? s.stop_volume_ratio
                        : s.target_volume_schedule.empty() ? s.target_volume
                                                           : sim.volume_target(sim.frame());
    // A target met and then lost: the shell's momentum carried it on (the volume constraint
    // moves each vertex a limited distance per step, volume_constraint.hpp), not a run too
    // short to get there.
    const int met = has_target ? frame_goal_met(history, goal, settled) : -1;
    const std::string end = "V/V0 " + volume_ratio_text(r.final_volume_ratio) + " (frame " +
                            std::to_string(r.frames_run) + ")";
    r.message =
        what + volume_ratio_text(goal) + " not reached: " +
        (!stalled.empty() ? stalled
         : met >= 0       ? "V/V0 came to it at frame " + std::to_string(met) +
                          " but did not stay there: " + end +
                          "; the volume constraint moves each vertex a limited distance per "
                          "step (less where contacts hold the shell), too little to stop the "
                          "shell's momentum (more frames or a slower ramp let it)"
                    : "the frames ran out at " + end) +
        "; V/V0 ended " + miss_text(r.final_volume_ratio, goal, has_target);
  }
  r.anisotropic_faces = sim.anisotropy_report().faces;
  r.region_inward_displacement = sim.region_inward_displacement();
  r.region_sinks = sim.region_sinks();
  r.outside_region_displacement = sim.outside_region_displacement();
  r.degenerate_faces = rest.degenerate_faces;
  r.mass_scaled_vertices = sim.mass_scaling().raised;
  r.max_mass_scale = sim.mass_scaling().largest_factor;
  r.excluded_contact_pairs = sim.excluded_contact_pairs();
  r.contact_distance = sim.options().collisions ? sim.options().collision.delta : 0.0;
  r.normalization_scale = sim.normalization().scale;
  // Into the storage taken before the first step: a run that has used all the memory there is
  // still returns its result.
  denormalize_into(sim.positions(), sim.normalization(), r.positions);
  try {
    obs.finished(view, r);
  } catch (const std::bad_alloc&) {
    fail_out_of_memory(r, "after the last step (in an observer)", mesh, last_pairs);
  }
  return r;
}

}  // namespace

}  // namespace shellcontract
