// The summary and the log row of a run, for every front end (run_report.hpp).
#include <iomanip>
#include <locale>
#include <set>
#include <sstream>
#include <string_view>

#include "core/arena_threads.hpp"
#include "core/decimal_text.hpp"
#include "core/kernels.hpp"
#include "mesh/file_safety.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/report.hpp"
#include "shellcontract/run.hpp"
#include "shellcontract/version.hpp"
#include "sim/target_ramp.hpp"

namespace shellcontract {

LogRow log_row(const FrameMetrics& m) {
  return {static_cast<double>(m.frame),
          m.time,
          m.volume_ratio,
          m.energies.membrane,
          m.energies.bending,
          m.energies.anisotropic,
          m.max_displacement,
          m.step_seconds * 1e3,
          m.solve_seconds * 1e3,
          m.collision.seconds * 1e3,
          static_cast<double>(m.collision.pairs_broad),
          static_cast<double>(m.collision.contacts),
          static_cast<double>(m.collision.rounds),
          static_cast<double>(m.collision.failsafe_vertices),
          static_cast<double>(m.new_intersections)};
}

std::string log_csv_header() {
  std::string s;
  for (std::size_t c = 0; c < LOG_COLUMN_COUNT; ++c) s += (c ? "," : "") + std::string(LOG_COLUMNS[c]);
  return s + "\n";
}

std::string log_csv_line(const LogRow& row) {
  std::ostringstream o;
  o.imbue(std::locale::classic());  // a point, not a host program's decimal comma
  o << std::setprecision(17);
  for (std::size_t c = 0; c < row.size(); ++c) o << row[c] << (c + 1 < row.size() ? ',' : '\n');
  return o.str();
}

std::vector<LogRow> log_csv_rows(const std::string& text, const std::string& name) {
  std::vector<LogRow> rows;
  std::size_t line = 1, at = text.find('\n');  // the header
  while (at != std::string::npos && at + 1 < text.size()) {
    ++line;
    const std::size_t begin = at + 1;
    at = text.find('\n', begin);
    const std::string_view row_text(text.data() + begin,
                                    (at == std::string::npos ? text.size() : at) - begin);
    LogRow row{};
    std::size_t from = 0;
    for (std::size_t c = 0; c < LOG_COLUMN_COUNT; ++c) {
      const std::size_t to = c + 1 < LOG_COLUMN_COUNT ? row_text.find(',', from) : row_text.size();
      const std::string_view field =
          row_text.substr(from, to == std::string_view::npos ? to : to - from);
      // A missing comma, or a field that is not all one number (parse_c_number: strtod's
      // reading in the "C" locale; the last field takes in any further commas, so more columns
      // are refused too): the text was changed after it was written.
      if (to == std::string_view::npos || !parse_c_number(field, row[c]))
        throw InputError(
            name + ": line " + std::to_string(line) + ": " +
            (to == std::string_view::npos
                 ? "fewer than the " + std::to_string(LOG_COLUMN_COUNT) + " columns"
                 : "'" + printable(field, 40) + "' (" + LOG_COLUMNS[c] + ") is not a number") +
            " (the file was edited or is damaged; a run never saves this)");
      from = to + 1;
    }
    rows.push_back(row);
  }
  return rows;
}

namespace {

/// An option's value as the summary records it: the value the run used, which the option takes
/// back, so that the recorded options rerun the run. The table's resolved value but for three:
/// the ramp a run of fewer than twice its frames shortens (target_ramp_used); `regions`, which
/// --region-at and --region-weights set themselves (Auto, Weights) and which a run given beside
/// them refuses: recorded as not given, their own entries holding the points and the weights'
/// file; and the options without effect in this run (options_without_effect, the rules of the
/// "has no effect" warnings: mu_a without an anisotropic energy, c10 under StVK, ...), recorded
/// empty as `young` and `thickness` are where no shell material ran, so that a reader sees which
/// values shaped the run. A rerun that leaves them out is the same run.
std::string summary_value(const OptionSpec& spec, const RunOptions& options,
                          const std::set<std::string>& unused) {
  if (unused.count(option_field(spec.name))) return {};
  if (spec.name == "target-ramp") return std::to_string(target_ramp_used(options.sim));
  if (spec.name == "regions" &&
      (!options.region_points.empty() || options.regions == RegionSource::Weights))
    return {};
  return spec.get(options);
}

}  // namespace

void write_run_summary(SummaryWriter& w, const InputReport& report, const RunOptions& options,
                       const RunResult& r, OptionSpelling spelling, const SummaryFiles* files) {
  const auto count = [&w](const char* key, std::size_t v) {
    w.add_integer(key, static_cast<long long>(v));
  };
  w.add_text("status", status_name(r.status));
  w.add_text("failure", r.message);
  w.add_integer("exit_code", files && files->exit_code ? *files->exit_code : r.exit_code());
  if (files) {
    w.add_text("input", files->input);
    w.add_text("output", files->output);
  }
  // Which build and kernels made the result (shellcontract/version.hpp): enough to rerun it.
  w.add_text("version", build_version());
  w.add_text("kernels", detail::kernels_in_use());
  count("vertices", report.vertices);
  count("faces", report.faces);
  count("components", report.components);
  w.add_bool("reoriented", report.reoriented);
  count("welded_vertices", report.welded_vertices);  // seam copies (mesh_io.hpp, "Seams")
  count("degenerate_faces", r.degenerate_faces);
  w.add_number("normalization_scale", r.normalization_scale);
  w.add_object("options", [&](SummaryWriter& o) {
    const std::set<std::string> unused = options_without_effect(options);
    for (const OptionSpec& spec : run_option_table())
      o.add_text(option_name(spec, spelling), summary_value(spec, options, unused));
  });
  w.add_integer("frames_run", r.frames_run);
  w.add_number("final_volume_ratio", r.final_volume_ratio);
  w.add_number("min_volume_ratio", r.min_volume_ratio);
  // null when nothing was to be reached: true would let a failed run pass a filter on it.
  if (options.sim.target_volume > 0.0 || options.sim.stop_volume_ratio > 0.0)
    w.add_bool("target_reached", r.target_reached);
  else
    w.add_null("target_reached");
  w.add_integer("frame_target_reached", r.frame_target_reached);
  w.add_number("wall_seconds", r.wall_seconds);
  // This process's time over this process's frames: a resumed run timed only its own part.
  const int timed_frames = r.frames_run - r.first_frame;
  w.add_number("mean_step_ms", timed_frames > 0 ? 1e3 * r.wall_seconds / timed_frames : 0.0);
  w.add_bool("collisions", options.sim.collisions);
  w.add_text("order_used", r.order == ConstraintOrder::Coloured ? "coloured" : "sequential");
  // options.threads records the option (0: every usable core), which reruns the run on another
  // machine; this is the count the run had here (results do not depend on it).
  w.add_integer("threads_used", arena_threads(options.sim.solver.threads));
  count("excluded_contact_pairs", r.excluded_contact_pairs);
  w.add_number("contact_distance", r.contact_distance);
  count("mass_scaled_vertices", r.mass_scaled_vertices);
  w.add_number("max_mass_scale", r.max_mass_scale);
  w.add_integer("new_intersections", r.new_intersections);
  count("regions", r.regions);
  count("anisotropic_faces", r.anisotropic_faces);
  w.add_number("region_inward_displacement", r.region_inward_displacement);
  w.add_number("outside_region_displacement", r.outside_region_displacement);
  w.add_numbers("region_sinks", r.region_sinks);
  w.add_object("table2", [&](SummaryWriter& t) {
    for (const auto& [name, value] : r.totals.per_step(r.frames_run)) t.add_number(name, value);
  });
  std::vector<std::string> warnings = report.warnings;
  for (const std::string& text : r.warnings) warnings.push_back(spell_options(text, spelling));
  w.add_texts("warnings", warnings);
}

}  // namespace shellcontract
