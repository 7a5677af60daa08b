// The formats of the format table (src/mesh/formats.hpp) and the formats a message or help text
// lists: the two sets the format tests compare.
#pragma once

#include <functional>
#include <regex>
#include <set>
#include <string>

#include "mesh/formats.hpp"

namespace shellcontract::test {

using Extensions = std::set<std::string>;

/// The table's rows that `keep` selects (a predicate or a bool member of MeshFormat).
template <class Keep>
Extensions rows(Keep keep) {
  Extensions out;
  for (const MeshFormat& f : MESH_FORMATS)
    if (std::invoke(keep, f)) out.insert(f.ext);
  return out;
}

/// The extensions a text lists after the last `after`, up to `stop`: its words, with or without
/// their dots, less the list's own words (a help text's line breaks fall out with the blanks).
inline Extensions listed(const std::string& text, const std::string& after = "expected ",
                         const std::string& stop = ")") {
  const std::size_t at = text.rfind(after);
  if (at == std::string::npos) return {"<no '" + after + "' in: " + text + ">"};
  std::string list = text.substr(at + after.size());
  list = list.substr(0, list.find(stop));
  static const Extensions GLUE = {"or", "and", "for", "an", "input", "of", "that", "format"};
  Extensions out;
  const std::regex word("[A-Za-z0-9]+");
  for (auto it = std::sregex_iterator(list.begin(), list.end(), word); it != std::sregex_iterator();
       ++it)
    if (!GLUE.count(it->str())) out.insert(it->str());
  return out;
}

}  // namespace shellcontract::test
