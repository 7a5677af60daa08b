// The run command's command line: its usage and exit-code texts for --help, and the library's
// option table as boost options in the task groups of run --help (run_command_line.hpp).
#include "run_command_line.hpp"

#include <algorithm>
#include <cstddef>
#include <limits>

#include "core/decimal_text.hpp"
#include "help_groups.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"

namespace shellcontract::cli {

namespace po = boost::program_options;

const char* const RUN_USAGE =
    "usage: shellcontract run INPUT -o OUTPUT [options]\n\n"
    "Contracts a closed triangle mesh (OFF, OBJ, PLY, STL, glTF .glb/.gltf) like a thin elastic\n"
    "shell under an outside pressure. The mesh is normalized to a unit bounding-box diagonal for\n"
    "the simulation (lengths and pressure below are in those units) and scaled back on output.\n"
    "Output keeps the input's vertex and face order. An OBJ or PLY output (and frame) of an input\n"
    "of the same format is the input file with new positions (OBJ: and normals): UVs, groups,\n"
    "materials, polygons and extra PLY properties are kept (docs/design/attributes.md); so is a\n"
    "glTF output of a glTF input (.glb to .glb, .gltf to .gltf: nodes, materials, textures, UVs\n"
    "kept; new positions and normals). A glTF input is read as the triangles its default scene\n"
    "draws, at their world positions. A mesh open only because its vertices are split along UV\n"
    "seams (copies at the same position) is welded for the simulation; the outputs keep every "
    "copy.\n\noutputs and general";

const char* const RUN_EXIT_CODES =
    "\nexit codes: 0 success, 1 bad usage (also: an output that could not be written, the others\n"
    "            written; an .stl output of a mesh with two vertices at one position, which an\n"
    "            STL reader merges), 2 bad input (mesh, face list, weights, checkpoint),\n"
    "            3 simulation failed, out of memory or a resource refused (the last good state\n"
    "            written; nothing if memory ran out before the first frame or while writing),\n"
    "            4 new self-intersections found by --validate, 5 the target volume or stop ratio\n"
    "            was not reached (result written); 3, 4 or 5 also when an output failed too,\n"
    "            130 interrupted by Ctrl-C, SIGTERM, SIGHUP or SIGUSR1 after the step it is in\n"
    "            (stderr names the frame; no result, log, summary, glTF or fields; the finished\n"
    "            --export-dir frames stay: remove them to rerun; with --checkpoint the state is\n"
    "            saved for --resume), or while the run is prepared (regions, contacts), before\n"
    "            the first step (nothing written, no checkpoint)\n";

void add_table_options(po::options_description& desc, std::map<std::string, std::string>& values,
                       std::map<std::string, bool>& switches,
                       std::map<std::string, std::vector<std::string>>& lists) {
  const RunOptions defaults;
  const auto& groups = run_help_groups();
  std::vector<po::options_description> sections;
  for (const auto& g : groups) sections.emplace_back(g.first, 100, 50);
  sections.emplace_back("other", 100, 50);
  for (const OptionSpec& o : run_option_table()) {
    std::size_t s = 0;
    while (s < groups.size() && std::find(groups[s].second.begin(), groups[s].second.end(),
                                          o.name) == groups[s].second.end())
      ++s;
    po::options_description& section = sections[s];
    const std::string key = o.short_name ? o.name + "," + std::string(1, o.short_name) : o.name;
    if (o.is_switch) {
      section.add_options()(key.c_str(), po::bool_switch(&switches[o.name]), o.help.c_str());
      continue;
    }
    if (o.repeatable) {  // every occurrence kept, set at once (joined by ';')
      section.add_options()(key.c_str(),
                            po::value(&lists[o.name])->composing()->value_name(o.value_name),
                            o.help.c_str());
      continue;
    }
    const std::string def = o.get(defaults);
    const std::string shown = run_help_shown_default(o.name);
    po::typed_value<std::string>* v = po::value(&values[o.name])->value_name(o.value_name);
    if (!def.empty()) v->default_value(def, shown.empty() ? def : shown);
    section.add_options()(key.c_str(), v, o.help.c_str());
  }
  for (const po::options_description& section : sections)
    if (!section.options().empty()) desc.add(section);
}

int frame_count(const std::string& option, const std::string& text) {
  constexpr long most = std::numeric_limits<int>::max();
  long n = 0;
  if (!parse_decimal_integer(text, n) || n < 1 || n > most)
    throw UsageError(option + ": '" + text + "' is not an integer in [1, " + std::to_string(most) +
                     "]");
  return static_cast<int>(n);
}

}  // namespace shellcontract::cli
