// The bending models (BendingModel) by name, with what --help says of each: the one list that
// --bending's parser and its --help are made from (option_table.cpp), and that the tests walk.
// Private to the library (included as "sim/bending_models.hpp").
#pragma once

#include <vector>

#include "shellcontract/simulation_options.hpp"
#include "sim/option_builders.hpp"

namespace shellcontract {

inline std::vector<option_builders::DescribedChoice<BendingModel>> bending_models() {
  return {{"isometric", BendingModel::Isometric, "the paper's, flat rest"},
          {"dihedral", BendingModel::Dihedral, "rest-aware"},
          {"none", BendingModel::None, ""}};
}

}  // namespace shellcontract
