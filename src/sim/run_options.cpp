#include "shellcontract/options.hpp"

#include <utility>

#include "material/registry.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/material.hpp"

namespace shellcontract {

ConstraintOrder order_for(OrderChoice choice) {
  return choice == OrderChoice::Sequential ? ConstraintOrder::Sequential : ConstraintOrder::Coloured;
}

std::vector<std::string> ineffective_options(const RunOptions& r) {
  const SimOptions& s = r.sim;
  std::vector<std::string> w;
  // Options by field; a front end spells `field` its own way (spell_options).
  auto check = [&](const char* field, bool no_effect, const std::string& why) {
    if (no_effect && r.given.count(field))
      w.push_back(std::string("`") + field + "` has no effect: " + why);
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
  check("inward", measure_only,
        "`measure_regions` without `regions`, `region_weights`, `region_at` or `aniso` only "
        "measures the regions, it does not contract them");
  // With `inward` projection k_A = kappa_A mu_A sqrt(A) scales with mu_A as the energy does, so
  // the projection is the same (GoldenPaths.InwardProjectionUnderPbdDoesNotDependOnMuA).
  check("mu_a", aniso && pbd,
        "a PBD projection does not depend on the stiffness (mu_A acts with `solver` xpbd; with "
        "`inward` projection k_A scales with it as the energy does)");
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
    check(name, shell_given && s.material != MaterialKind::MooneyRivlin,
          "`young` and `thickness` set mu and lambda (leave both out to give mu and lambda)");
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
  check("air_balance", !(s.pressure > 0.0) && !(s.target_volume > 0.0),
        "the air balances a compressing pressure, and `pressure` is not > 0");
  if (s.stop_volume_ratio > 0.0 && s.target_volume <= 0.0 && s.air_balance > 0.0 &&
      s.stop_volume_ratio <= s.air_balance)
    w.push_back("`stop_volume_ratio` " + shortest_text(s.stop_volume_ratio) +
                " is at or below the air balance " + shortest_text(s.air_balance) +
                ": the air inside stops the shell above it, so the run may stall first (lower "
                "`air_balance`, 0 = no air)");
  // The paper's isometric bending is flat at rest. Its PBD projection is a correction that the
  // membrane outweighs, but under the XPBD shell it carries the material's bending stiffness, so
  // a closed curved mesh is driven flat and loses volume with no pressure at all.
  if (s.bending == BendingModel::Isometric && !pbd && r.given.count("bending"))
    w.push_back("`bending` isometric has a flat rest state: under `solver` xpbd it drives a curved "
                "shell flat, so the mesh contracts even at `pressure` 0 (it is the paper's bending "
                "for `solver` pbd; the default dihedral bending is at rest on the input)");
  return w;
}

}  // namespace shellcontract
