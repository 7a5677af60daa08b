// How `shellcontract run --help` groups the option table by task, and the defaults it shows
// where the table's plain default does not apply under the default solver. Only presentation:
// the options themselves, their parsing and their defaults come from the one option table.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace shellcontract::cli {

/// The task groups of run --help in the order shown, each with the table options it holds.
/// An option of the table that no group names is shown under "other".
inline const std::vector<std::pair<std::string, std::vector<std::string>>>& run_help_groups() {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> groups = {
      {"how much it contracts",
       {"target-volume", "target-ramp", "pressure", "air-balance", "stop-volume-ratio", "frames",
        "pressure-model"}},
      {"material",
       {"material", "young", "poisson", "thickness", "mu", "lambda", "c10", "c01", "mass",
        "density"}},
      {"bending", {"bending", "k-b"}},
      {"solver", {"solver", "dt", "iterations", "damping", "order", "threads"}},
      {"local contraction (regions that sink in)",
       {"regions", "region-weights", "region-at", "region-shrink", "region-max-area", "inward",
        "dimple", "aniso", "mu-a", "fiber", "fiber-target", "k-a", "inversion-aware",
        "measure-regions"}},
      {"collisions",
       {"collisions", "delta", "collision-rounds", "validate", "warm-start",
        "speculative-broad-phase"}},
  };
  return groups;
}

/// The default run --help shows for an option whose table default is replaced under the
/// default solver (xpbd) by a value derived from other options; empty to show the table's.
inline std::string run_help_shown_default(const std::string& name) {
  // The table's values apply where the shell material does not: under --solver pbd or
  // --material mooney-rivlin (mu, lambda, k_B), and with --bending isometric (k_B); run_plan.cpp.
  if (name == "mu" || name == "lambda") return "derived from --young, else 1";
  if (name == "k-b") return "derived from --young, else 0.01";
  if (name == "damping") return "0.1, pbd: 0.2";
  return {};
}

}  // namespace shellcontract::cli
