#include <cmath>
#include <set>
#include <utility>

#include "material/registry.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/material.hpp"
#include "shellcontract/options.hpp"
#include "sim/target_ramp.hpp"

namespace shellcontract {

ConstraintOrder order_for(OrderChoice choice) {
  return choice == OrderChoice::Sequential ? ConstraintOrder::Sequential : ConstraintOrder::Coloured;
}

namespace {

/// Under pbd a stiffness can change only the solver's skip floor, 1e-16 x the stiffness of the
/// energies in use (src/pbd/solver.cpp: the membrane's, and mu_A's with an aniso energy). mu_A
/// moves it beside the membrane's, so its "no effect" is said of the step: it may still move
/// which faces near rest are skipped, and so the result by small amounts. The membrane's own
/// scale moves the floor with the energy, so nothing, unless an aniso energy's mu_A sets it.
const char* const PBD_STEP_ONLY =
    "has no effect on the PBD projection's step (only on which faces "
    "near rest it skips): ";
const char* const PBD_SCALE =
    "has no effect on the PBD projection's step (nor, without an `aniso` energy, on which faces "
    "near rest it skips): ";

/// The options that scale the membrane's energy without changing its form: under pbd (math-spec
/// 9.1(a)) the step E/|grad E|^2 grad E does not depend on them. --mu-a is checked with the other
/// anisotropy options. One line each, for the options given.
void pbd_scale_warnings(const RunOptions& r, std::vector<std::string>& w) {
  const SimOptions& s = r.sim;
  if (s.solver.kind != SolverKind::Pbd) return;
  const std::string scale = "a PBD projection does not depend on the stiffness's scale";
  const auto given = [&r](const char* field) { return r.given.count(field) > 0; };
  const MaterialParams& m = s.material_params;
  if (s.material == MaterialKind::MooneyRivlin) {
    // `young`, `thickness` under Mooney-Rivlin are warned about below (its membrane does not
    // read them). With C01 0 the energy is C10 times a fixed form; with both, only C01/C10 acts.
    if (given("c10") && m.c01 == 0.0)
      w.push_back(std::string("`c10` ") + PBD_SCALE + scale +
                  ", and with `c01` 0 C10 only scales the Mooney-Rivlin energy");
    else if (given("c10") && given("c01"))
      w.push_back("`c10` and `c01` act under `solver` pbd by their ratio C01/C10 alone (here " +
                  shortest_text(m.c01 / m.c10) + "): their common scale " + PBD_SCALE + scale);
    return;
  }
  const bool shell_given = given("young") || given("thickness");
  for (const char* field : {"young", "thickness"})
    if (given(field))
      w.push_back(std::string("`") + field + "` " + PBD_SCALE +
                  "the membrane acts by lambda/mu alone, which `poisson` sets (`young` and "
                  "`thickness` set the bending k_B only under `solver` xpbd)");
  // `mu` and `lambda` beside `young` or `thickness` are warned about as set by those.
  if (given("mu") && given("lambda") && !shell_given)
    w.push_back("`mu` and `lambda` act under `solver` pbd by their ratio lambda/mu alone (here " +
                shortest_text(m.lambda / m.mu) + "): their common scale " + PBD_SCALE + scale);
}

/// Under xpbd k_B is a stiffness, which the shell material (young, thickness) sets for the
/// dihedral bending only (resolve_run_options). Elsewhere, unless given, it is `k_b`'s 0.01, the
/// PBD-era multiplier: over 40,000 times the default shell's, so the same shell keeps much more of
/// its volume. Said, with the k_B the shell would have, so that `k_b` can give it: for the
/// dihedral bending without a shell material (`mu` or `lambda` given, or Mooney-Rivlin), and for
/// the isometric bending always (its energy about a flat rest is the dihedral's to second order,
/// spec.md 8.3, so the plate's k_B is the same; docs/math/bending-from-material.md).
void fallback_k_b_warning(const RunOptions& r, std::vector<std::string>& w) {
  const SimOptions& s = r.sim;
  const bool isometric = s.bending == BendingModel::Isometric;
  if (s.solver.kind != SolverKind::Xpbd || s.bending == BendingModel::None ||
      r.given.count("k_b") || (!isometric && r.young.has_value()))
    return;
  const std::string used = "the bending k_B is " + shortest_text(s.solver.k_bending);
  const std::string give = ": give `k_b` for it";
  const auto valid = [](double young, double nu, double h) {
    return young > 0.0 && std::isfinite(young) && h > 0.0 && std::isfinite(h) && nu > -1.0 &&
           nu < 1.0;
  };
  if (r.young && r.thickness) {  // the isometric bending beside a shell material
    if (!valid(*r.young, r.poisson, *r.thickness)) return;  // refused by the checks after this
    w.push_back(used +
                " (`k_b`'s default: the shell material sets k_B for the dihedral bending "
                "only); this shell of `young` " +
                shortest_text(*r.young) + ", `thickness` " + shortest_text(*r.thickness) +
                " and `poisson` " + shortest_text(r.poisson) + " has k_B " +
                shortest_text(dihedral_k_bending_from_young(*r.young, r.poisson, *r.thickness)) +
                give);
    return;
  }
  const MaterialParams& m = s.material_params;
  const bool mooney = s.material == MaterialKind::MooneyRivlin;
  // The small-strain shell of this membrane: plane stress gives mu = E h / (2 (1 + nu)) and
  // lambda = E h nu / (1 - nu^2), so nu = lambda / (lambda + 2 mu) and E h = 2 mu (1 + nu);
  // Mooney-Rivlin's membrane is incompressible (nu 1/2) with mu = 2 (C10 + C01).
  const double mu = mooney ? 2.0 * (m.c10 + m.c01) : m.mu;
  const double nu = mooney ? 0.5 : m.lambda / (m.lambda + 2.0 * m.mu);
  const double h = DEFAULT_SHELL_THICKNESS;
  const double young = 2.0 * mu * (1.0 + nu) / h;
  // mu > 0 and mu + lambda > 0 (check_sim_options) hold nu in (-1, 1); a caller's fields that
  // do not are refused by the checks after this.
  if (!valid(young, nu, h)) return;
  const double shell_k_b = dihedral_k_bending_from_young(young, nu, h);
  const double default_k_b =
      dihedral_k_bending_from_young(DEFAULT_SHELL_YOUNG, RunOptions{}.poisson, h);
  std::string why = mooney ? "`material` mooney-rivlin has no shell material"
                           : "`mu` or `lambda` given replaces the default shell material";
  if (isometric) why = "the shell material sets k_B for the dihedral bending only, and " + why;
  // The isometric bending takes k_B from no shell material, so only `k_b` gives it.
  const std::string other =
      isometric ? ""
      : mooney  ? ", or `young` and `thickness` (which set only k_B here)"
                : ", or the membrane by `young`, `thickness` and `poisson` instead of `mu` and "
                  "`lambda`";
  w.push_back(used + " (`k_b`'s " + (isometric ? "default: " : "fallback: ") + why +
              "; the default shell's k_B is " + shortest_text(default_k_b) +
              "); this membrane as a shell of `thickness` " + shortest_text(h) + " has k_B " +
              shortest_text(shell_k_b) + give + other);
}

/// The rules of the options that have no effect with the others, for ineffective_options (the
/// warnings, for the options given) and options_without_effect (every option without effect,
/// given or not, which the summary records empty): one set of rules for both.
struct OptionReview {
  std::vector<std::string> warnings;
  std::set<std::string> unused;
};

OptionReview review_options(const RunOptions& r) {
  const SimOptions& s = r.sim;
  OptionReview review;
  std::vector<std::string>& w = review.warnings;
  // Options by field; a front end spells `field` its own way (spell_options). `check`: the option
  // has no effect here whatever its value; `replaced`: a value given for it is replaced by
  // another option's, and the run used the value that replaced it.
  auto replaced = [&](const char* field, bool no_effect, const std::string& why) {
    if (no_effect && r.given.count(field))
      w.push_back(std::string("`") + field + "` has no effect: " + why);
  };
  auto check = [&](const char* field, bool no_effect, const std::string& why) {
    if (no_effect) review.unused.insert(field);
    replaced(field, no_effect, why);
  };
  const bool aniso = s.solver.aniso != AnisoKind::None;
  const bool regions = r.regions != RegionSource::None;
  const bool pbd = s.solver.kind == SolverKind::Pbd;
  const bool k_a_projected = aniso && pbd && s.inward_term == InwardTerm::Projection;
  check("region_max_area", r.regions != RegionSource::Auto,
        "it filters the regions of `regions` auto");
  check("region_shrink", !regions || s.inward_term == InwardTerm::None || k_a_projected,
        "the local contraction acts on the regions of `regions` (or `aniso`) with `inward` "
        "volume or force");
  check("dimple", !regions || s.inward_term != InwardTerm::Volume,
        "it is the shape of the dimples of `inward` volume on the regions of `regions`");
  check("k_a", !k_a_projected, "kappa_A acts with `aniso`, `inward` projection and `solver` pbd");
  check("inward", !regions, "the inward term acts on the regions of `regions` (or `aniso`)");
  // measure_regions with no region source and no aniso selects the regions only to measure them
  // (resolve_run_options sets inward none): an inward term given there is overridden.
  const bool measure_only = r.measure_regions && r.regions == RegionSource::Auto && !aniso &&
                            !r.given.count("regions") && r.region_points.empty();
  replaced("inward", measure_only,
           "`measure_regions` without `regions`, `region_weights`, `region_at` or `aniso` only "
           "measures the regions, it does not contract them");
  // With `inward` projection k_A = kappa_A mu_A sqrt(A) scales with mu_A as the energy does, so
  // the projection is the same (GoldenPaths.InwardProjectionUnderPbdDoesNotDependOnMuA).
  if (aniso && pbd && r.given.count("mu_a"))
    w.push_back(std::string("`mu_a` ") + PBD_STEP_ONLY +
                "a PBD projection does not depend on the stiffness (mu_A acts with `solver` xpbd; "
                "with `inward` projection k_A scales with it as the energy does)");
  pbd_scale_warnings(r, w);
  for (const char* name : {"mu_a", "fiber", "inversion_aware"})
    check(name, !aniso, "no `aniso` energy is chosen");
  check("fiber_target", s.solver.aniso != AnisoKind::ActiveFiber,
        "it is the active fibre's (`aniso` active-fiber)");
  for (const char* name : {"c10", "c01"})
    check(name, s.material != MaterialKind::MooneyRivlin,
          "it is a Mooney-Rivlin parameter (`material` mooney-rivlin)");
  for (const char* name : {"mu", "lambda"})
    check(name, s.material == MaterialKind::MooneyRivlin, "Mooney-Rivlin takes `c10` and `c01`");
  // resolve_default_run: a shell material given by `young` or `thickness` sets mu and lambda,
  // over values given for them.
  const bool shell_given = r.given.count("young") || r.given.count("thickness");
  for (const char* name : {"mu", "lambda"})
    replaced(name, shell_given && s.material != MaterialKind::MooneyRivlin,
             "`young` and `thickness` set mu and lambda (leave both out to give mu and lambda)");
  fallback_k_b_warning(r, w);
  // Mooney-Rivlin's membrane reads only c10 and c01: from the shell material it takes at most the
  // bending k_B (xpbd, dihedral bending, `k_b` not given), never mu and lambda.
  if (s.material == MaterialKind::MooneyRivlin && shell_given) {
    const bool sets_k_b = s.solver.kind == SolverKind::Xpbd &&
                          s.bending == BendingModel::Dihedral && !r.given.count("k_b");
    const std::string membrane = "the Mooney-Rivlin membrane takes `c10` and `c01`";
    if (sets_k_b) w.push_back("`young` and `thickness` set only the bending k_B here: " + membrane);
    for (const char* name : {"young", "thickness", "poisson"})
      check(name, !sets_k_b,
            membrane + ", and `k_b` is given or the bending is not xpbd's dihedral");
  }
  check("density", s.mass == MassModel::Unit, "`mass` unit gives every vertex the mass 1");
  check("poisson", !r.young.has_value(), "the Poisson ratio is used with `young` and `thickness`");
  check("k_b", s.bending == BendingModel::None, "`bending` none");
  for (const char* name : {"delta", "collision_rounds", "warm_start", "speculative_broad_phase"})
    check(name, !s.collisions, "`collisions` off");
  check("target_ramp",
        !(s.target_volume > 0.0) && !(regions && s.inward_term == InwardTerm::Volume),
        "it is the ramp of `target_volume` and of the regions' shrink (`inward` volume)");
  // The keys time the volume; the ramp still times the regions' sink (simulator_regions.cpp).
  check("target_ramp",
        !s.target_volume_schedule.empty() && !(regions && s.inward_term == InwardTerm::Volume),
        "the keys of `target_volume` set its timing");
  // A ramp longer than half the frames is shortened to it (target_ramp.hpp), so a target meant
  // for the last frame is reached half way; keys time it to the frame.
  if (r.given.count("target_ramp") && s.target_ramp_frames > target_ramp_used(s) &&
      ((s.target_volume > 0.0 && s.target_volume_schedule.empty()) ||
       (regions && s.inward_term == InwardTerm::Volume)))
    w.push_back("`target_ramp` " + std::to_string(s.target_ramp_frames) +
                " is more than half of `frames` (" + std::to_string(s.frames) +
                "): the run shortens it to " + std::to_string(target_ramp_used(s)) +
                ", so the ramp ends there and its end value is held over the rest" +
                (s.target_volume > 0.0
                     ? "; to reach the target at the last frame, give it as keys (`target_volume` "
                       "\"0:1, " +
                           std::to_string(s.frames) + ":" + shortest_text(s.target_volume) + "\")"
                     : std::string()));
  // A key after the last frame is never reached: the run ends part way to it.
  for (const auto& [name, keys] : {std::pair<const char*, const Schedule*>{
                                       "target_volume", &s.target_volume_schedule},
                                   {"pressure", &s.pressure_schedule}})
    if (!keys->empty() && keys->last_frame() > s.frames)
      w.push_back(std::string("`") + name + "`: the key at frame " +
                  std::to_string(keys->last_frame()) + " comes after the last frame (" +
                  std::to_string(s.frames) + "); the run ends on the schedule's value there, " +
                  shortest_text(keys->at(s.frames)));
  // No check of `pressure` or `air_balance` under `target_volume`: the constraint decides the
  // volume, but both still push between its projections and change the path and the shape
  // (docs/math/volume-control.md, section 1).
  // At pressure 0 with no keys both models give no force (pressure_forces scales by P), and the
  // regions' extra load is 2 S P or the model-free P_A: nothing left to model.
  check("pressure_model", s.pressure == 0.0 && s.pressure_schedule.empty(),
        "there is no pressure to model (`pressure` 0, no keys)");
  check("air_balance", !(s.pressure > 0.0) && !(s.target_volume > 0.0),
        "the air balances a compressing pressure, and `pressure` is not > 0");
  if (s.stop_volume_ratio > 0.0 && s.target_volume <= 0.0 && s.air_balance > 0.0 &&
      s.stop_volume_ratio <= s.air_balance)
    w.push_back("`stop_volume_ratio` " + shortest_text(s.stop_volume_ratio) +
                " is at or below the air balance " + shortest_text(s.air_balance) +
                ": the air inside stops the shell above it, so the run may stall first (lower "
                "`air_balance`, 0 = no air)");
  // The paper's isometric bending is flat at rest. Its PBD projection is a correction that the
  // membrane outweighs, but under xpbd k_B is an energy scale (0.01 unless given, far stiffer
  // than the shell's: fallback_k_b_warning), so a closed curved mesh is driven flat and loses
  // volume with no pressure at all.
  if (s.bending == BendingModel::Isometric && !pbd && r.given.count("bending"))
    w.push_back("`bending` isometric has a flat rest state: under `solver` xpbd it drives a curved "
                "shell flat, so the mesh contracts even at `pressure` 0 (it is the paper's bending "
                "for `solver` pbd; the default dihedral bending is at rest on the input)");
  return review;
}

}  // namespace

std::vector<std::string> ineffective_options(const RunOptions& r) {
  return review_options(r).warnings;
}

std::set<std::string> options_without_effect(const RunOptions& r) {
  return review_options(r).unused;
}

}  // namespace shellcontract
