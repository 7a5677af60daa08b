// shellcontract regions IN [-o OUT.ply] [--face-list FILE] [--method caps|tips|parts] [thresholds]: shows
// the local spherical regions that `run --regions auto` would choose (or, opt-in, the tip or part
// finder's).
// Exit 0 ok, 1 bad usage (also an unwritable output), 2 bad input mesh.
#include "shellcontract/regions.hpp"

#include <algorithm>
#include <boost/program_options.hpp>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "command_line.hpp"
#include "commands.hpp"
#include "core/classic_locale.hpp"
#include "core/decimal_text.hpp"
#include "geometry/curvature.hpp"
#include "mesh/eigen_point_map.hpp"
#include "output_paths.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "stage_notice.hpp"

namespace shellcontract::cli {


namespace {

namespace po = boost::program_options;

constexpr const char* REGIONS_USAGE =
    R"(usage: shellcontract regions INPUT [-o OUT.ply] [--face-list FILE] [--method caps|tips|parts] [thresholds]

Finds the local spherical regions (bumps, heads, fingertips) of a closed mesh by curvature, the
ones 'run --regions auto' uses, and prints them with their face count and area fraction ('-'
where a region has no fitted sphere). With -o it also writes the mesh as an ASCII PLY with one
colour per region (grey = none), a per-face 'region' id and per-vertex 'mean_curvature' /
'gaussian_curvature' (input units); with --face-list, the regions as a face list.

Each region is a compact cap on a sphere (an ear, a head, a fingertip): seeds at maxima of the
smoothed mean curvature grow geodesic discs while a sphere fits them (--fit-tolerance), the caps
are ranked by the angle they span and kept when round (--max-compactness), curved (--min-cap-angle,
--contrast) and of a local size (--min-area-fraction, --max-area-fraction); caps on one part join
into one region, clipped to a hemisphere of its fitted sphere. --region-at X,Y,Z
(repeatable, or X,Y,Z;X,Y,Z as for run) instead picks the cap around the surface point nearest
to each point, the largest within --max-area-fraction (its one-ring where no convex sphere fits
there, or none within the bound), with a line 'at X, Y, Z (D from the point given)' under its
row: the surface point it grew from. A point farther from the surface than 1.5 % of the bounding
box's diagonal (a sphere's centre from this table, a point in Blender's Z-up world for a Y-up
file) is a warning. Every threshold is a ratio, so scaling or rotating the mesh does not change
the result.

--method tips (opt-in) finds the ends of protrusions instead (the end of an arm or a foot, an
ear, a fingertip): a disc around each tip, grown until it wraps round the end or meets a
concave crease (docs/math/tip-finder.md). It reads --max-concave-fraction, --max-compactness,
--min-faces and the area fractions; --fit-tolerance, --min-cap-angle, --contrast and
--region-at do not apply and are refused. Pass its --face-list to 'run --regions FILE'.

--method parts (opt-in) keeps the tip finder's ends and adds the cap finder's regions that tip
regions cover at most half of (heads, bumps on a body), each grown to the ball of its fitted
sphere; a tip region mostly inside such a region gives way to it (docs/math/part-finder.md). It
reads the options of both finders; not --region-at.

A face-list line is one region: its 0-based face ids, separated by spaces. 'run --regions FILE'
also reads a strength in front of a line, 'S: ids' with S in [0, 1] (the share of
--region-shrink that region sinks with; 1 without one); this command writes none.

exit codes: 0 success, 1 bad usage or unwritable output, 2 bad input (the mesh cannot be used),
            3 memory ran out or the system refused a resource (a thread, an open file),
            130 interrupted (Ctrl-C, SIGTERM)

options)";

/// The points of the --region-at values, read by `run --region-at`'s own entry of the option
/// table, so that both commands take the same forms (repeated, or X,Y,Z;X,Y,Z). UsageError
/// naming the option by field, as the table's entries do (spell_options spells it).
std::vector<Vec3> parse_region_points(const std::vector<std::string>& values) {
  std::string joined;
  for (const std::string& v : values) joined += (joined.empty() ? "" : ";") + v;
  for (const OptionSpec& spec : run_option_table())
    if (spec.name == "region-at") {
      RunOptions run;
      spec.set(run, joined);
      return run.region_points;
    }
  throw std::logic_error("the run option table has no region-at");
}

/// --method's value (the library's names); UsageError naming the allowed values otherwise.
RegionMethod parse_method(const std::string& text) {
  if (const std::optional<RegionMethod> m = region_method_named(text)) return *m;
  throw UsageError("--method '" + text + "': expected " + region_method_names());
}

/// A coordinate with its sign, to `decimals` decimals without trailing zeros ("+0", "-0.26287",
/// "+512345.07123"); in %g with `digits` significant digits where fixed-point would be long (a
/// mesh at 1e20 or 1e-20).
std::string coordinate(double v, int decimals, int digits) {
  std::string s;
  if (decimals >= 0 && decimals <= 20 && std::abs(v) < 1e15) {
    s = fixed_text(v, decimals);
    if (s.find('.') != std::string::npos) {
      s.erase(s.find_last_not_of('0') + 1);
      if (s.back() == '.') s.pop_back();
    }
    if (s == "-0") s = "0";
  } else {
    s = general_text(v, digits);
  }
  return s[0] == '-' ? s : "+" + s;
}

/// "+x, +y, +z" to a hundred-thousandth of the mesh's bounding-box diagonal: an `at` point fed
/// back as --region-at lands where it was. Four significant digits, as before, placed a 1.9-unit
/// statue's point at northing 5412345 to a thousand units, hundreds of diagonals off.
std::string point_coordinates(const Vec3& p, double diagonal, double largest) {
  int decimals = 17, digits = 17;
  if (diagonal > 0.0 && std::isfinite(diagonal) && std::isfinite(largest)) {
    decimals = std::max(0, static_cast<int>(std::ceil(-std::log10(diagonal))) + 5);
    digits = std::clamp(
        static_cast<int>(std::ceil(std::log10(std::max(largest, diagonal) / diagonal))) + 6, 6, 17);
  }
  return coordinate(p.x(), decimals, digits) + ", " + coordinate(p.y(), decimals, digits) + ", " +
         coordinate(p.z(), decimals, digits);
}

/// The regions as an aligned table: one row per region (id order); under a --region-at region's
/// row, a line starting with "at" (no id: parsers that take rows by their id skip it) with the
/// surface point it grew from and that point's distance from the point given. Points are
/// written to the precision of the mesh `x` (point_coordinates).
std::string region_table(const RegionReport& report, const Positions& x) {
  double diagonal = 0.0, largest = 0.0;
  if (x.rows() > 0) {
    diagonal = (x.colwise().maxCoeff() - x.colwise().minCoeff()).norm();
    largest = x.cwiseAbs().maxCoeff();
  }
  // The centres first: the column is as wide as the widest (a mesh far from the origin needs
  // more than the 36 characters of one near it).
  std::vector<std::string> centres;
  std::size_t width = 36;
  for (const RegionSummary& s : report.regions) {
    // A region without a sphere (a --region-at one-ring) has no centre, radius, fit or angle.
    centres.push_back(s.fitted ? point_coordinates(s.centre, diagonal, largest) : "-");
    width = std::max(width, centres.back().size() + 1);
  }
  ClassicOStringStream t;
  t << std::fixed;
  t << "  id  " << std::left << std::setw(static_cast<int>(width)) << "centre (x, y, z)"
    << std::right << "  radius      area %   faces  compact.  residual  angle\n";
  for (std::size_t r = 0; r < report.regions.size(); ++r) {
    const RegionSummary& s = report.regions[r];
    // Fixed-point for the usual sizes; a mesh at 1e150 or 1e-150 gets exponents, not 150 digits.
    ClassicOStringStream radius, residual, angle;
    if (!s.fitted)
      radius << '-';
    else if (std::abs(s.radius) >= 1e-4 && std::abs(s.radius) < 1e6)
      radius << std::fixed << std::setprecision(4) << s.radius;
    else
      radius << ' ' << std::setprecision(4) << s.radius;  // the centre may fill its column
    if (s.fitted)
      residual << std::fixed << std::setprecision(3) << s.residual;
    else
      residual << '-';
    if (s.fitted)
      angle << std::fixed << std::setprecision(0) << s.cap_angle_deg;
    else
      angle << '-';
    t << std::setw(4) << r << "  " << std::left << std::setw(static_cast<int>(width)) << centres[r]
      << std::right << std::setw(10) << radius.str() << std::setprecision(2) << std::setw(10)
      << 100.0 * s.area_fraction << std::setw(8) << s.faces << std::setw(10) << s.compactness
      << std::setw(10) << residual.str() << std::setw(6) << angle.str() << '\n';
    if (r < report.points.size()) {  // as the centre is written
      const RegionPoint& p = report.points[r];
      ClassicOStringStream distance;
      // A point near the largest doubles is farther than a double holds: said so, not "inf".
      if (std::isfinite(p.distance))
        distance << std::defaultfloat << std::setprecision(4) << p.distance;
      else
        distance << "more than " << std::setprecision(2) << std::numeric_limits<double>::max();
      t << "      at " << point_coordinates(p.surface_point, diagonal, largest) << " ("
        << distance.str() << " from the point given)\n";
    }
  }
  return t.str();
}

/// Refuses an option given an empty value ("--fit-tolerance ''", "--min-faces="), as `run`
/// words it: Boost's conversion of "" to a number says only "the argument for option ... is
/// invalid", and refuse_empty_values sees text options alone.
/// @throws UsageError naming the option
void refuse_empty_numbers(int argc, char** argv, const po::options_description& options) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--") return;
    if (arg.size() < 3 || arg.compare(0, 2, "--") != 0) continue;
    const std::size_t eq = arg.find('=');
    const std::string name = arg.substr(2, eq == std::string::npos ? std::string::npos : eq - 2);
    const po::option_description* o = nullptr;
    try {
      o = options.find_nothrow(name, true);
    } catch (const po::error&) {  // an ambiguous abbreviation: the parser's message
    }
    if (!o || o->semantic()->max_tokens() == 0) continue;
    const bool empty =
        eq != std::string::npos ? eq + 1 == arg.size() : i + 1 < argc && argv[i + 1][0] == '\0';
    if (empty)
      throw UsageError("--" + o->long_name() + ": empty; give a value or leave the option out");
    if (eq == std::string::npos) ++i;  // its value, which may start with "--"
  }
}

// A default as the user would type it ("0.3"), not Boost's full round-trip digits
// ("0.29999999999999999").
std::string shown(double value) {
  ClassicOStringStream text;
  text << value;
  return text.str();
}

/// The numeric options from their text (`number_text`, by option name), each as run reads its
/// own: a number by parse_decimal, --min-faces by parse_decimal_integer (no blanks, no inf or
/// nan, nothing out of a double's range); their ranges are check_region_options'.
/// @throws UsageError naming the option
void read_region_numbers(const std::map<std::string, std::string>& number_text,
                         RegionOptions& options) {
  const std::vector<std::pair<const char*, double*>> reals{
      {"fit-tolerance", &options.fit_tolerance},
      {"max-concave-fraction", &options.max_concave_fraction},
      {"min-cap-angle", &options.min_cap_angle_deg},
      {"contrast", &options.min_curvature_contrast},
      {"max-compactness", &options.max_compactness},
      {"min-area-fraction", &options.min_area_fraction},
      {"max-area-fraction", &options.max_area_fraction}};
  for (const auto& [name, field] : reals) {
    const std::string& text = number_text.at(name);
    if (!parse_decimal(text, *field))
      throw UsageError(std::string("--") + name + ": '" + text + "' is not a number");
  }
  const std::string& faces = number_text.at("min-faces");
  long n = 0;
  if (!parse_decimal_integer(faces, n))
    throw UsageError("--min-faces: '" + faces + "' is not an integer");
  // Beyond an int: refused before the narrowing (check_region_options refuses the rest below 1).
  constexpr long most = std::numeric_limits<int>::max();
  if (n < 0 || n > most)
    throw UsageError("--min-faces: '" + faces + "' is not an integer in [1, " +
                     std::to_string(most) + "]");
  options.min_faces = static_cast<int>(n);
}

}  // namespace

int command_regions(int argc, char** argv) {
  std::string input, output, face_list, method = "caps";
  std::vector<std::string> points;
  std::vector<Vec3> at;
  bool stage_times = false;
  RegionOptions options;
  // The numbers as text, read after parsing by the grammar every command reads numbers with
  // (read_region_numbers): Boost's conversions took "1e-400" as 0 and had words of their own.
  std::map<std::string, std::string> number_text;
  po::options_description visible;
  // clang-format off
  visible.add_options()
      ("help,h", "show this help")
      ("output,o", po::value(&output), "write the mesh as a .ply (face colours, region ids, curvature); "
                                       "without it, only the table (and --face-list)")
      ("face-list", po::value(&face_list), "also write the regions as a face-list file (one line per region, "
                                           "0-based face ids; the format 'run --regions FILE' reads, where a "
                                           "line may also start with a strength 'S:', S in [0, 1])")
      ("method", po::value(&method)->default_value(method), "caps (spherical caps from curvature seeds), tips "
                                                           "(opt-in: the ends of protrusions) or parts (opt-in: "
                                                           "tips with the caps' heads and bumps)")
      ("stage-times", po::bool_switch(&stage_times), "also print the wall and processor seconds of the "
                                                     "finder's stages on stderr (the cap finder's; none "
                                                     "for tips or --region-at)")
      ("region-at", po::value(&points)->composing(), "X,Y,Z: the cap around the surface point nearest to "
                                                      "this point (repeatable, or X,Y,Z;X,Y,Z; replaces the "
                                                      "automatic search)")
      ("fit-tolerance", po::value(&number_text["fit-tolerance"])->default_value(shown(options.fit_tolerance)),
       "growth: RMS distance to the fitted sphere at most this fraction of its radius")
      ("max-concave-fraction", po::value(&number_text["max-concave-fraction"])->default_value(shown(options.max_concave_fraction)),
       "growth: at most this share of a disc may be concave")
      ("min-cap-angle", po::value(&number_text["min-cap-angle"])->default_value(shown(options.min_cap_angle_deg)),
       "keep caps spanning at least this angle, degrees (geodesic radius / sphere radius; a hemisphere is 90)")
      ("contrast", po::value(&number_text["contrast"])->default_value(shown(options.min_curvature_contrast)),
       "keep caps whose curvature 1/radius is at least this multiple of the area-weighted median |H|")
      ("max-compactness", po::value(&number_text["max-compactness"])->default_value(shown(options.max_compactness)),
       "keep caps with perimeter^2 / (4 pi area) at most this (> 0; 1 = a flat disc, 0.5 = a "
       "hemisphere, larger = longer or more ragged)")
      ("min-faces", po::value(&number_text["min-faces"])->default_value(std::to_string(options.min_faces)), "keep caps with at least this many faces")
      ("min-area-fraction", po::value(&number_text["min-area-fraction"])->default_value(shown(options.min_area_fraction)),
       "drop regions smaller than this fraction of the total area")
      ("max-area-fraction", po::value(&number_text["max-area-fraction"])->default_value(shown(options.max_area_fraction)),
       "drop regions larger than this fraction of the total area (not local)");
  // clang-format on
  try {
    refuse_empty_numbers(argc, argv, visible);
    const po::variables_map vm = parse_command_line(argc, argv, visible, input);
    if (vm.count("help")) {
      std::cout << REGIONS_USAGE << '\n' << visible << '\n';
      return static_cast<int>(ExitCode::Success);
    }
    if (input.empty()) throw UsageError("missing INPUT mesh");
    if (!output.empty() && lower_extension(output) != "ply")
      throw UsageError("the output must be a .ply file (got '" + output + "')");
    options.method = parse_method(method);
    read_region_numbers(number_text, options);
    // Each option with its value and range, the area fractions with both values (spelled below).
    check_region_options(options);
    if (options.method != RegionMethod::Caps && !points.empty())
      throw UsageError("--region-at grows caps; it does not apply with --method " + method);
    // The cap finder's shape tests: given with the tip finder they would do nothing, unsaid.
    for (const char* name : {"fit-tolerance", "min-cap-angle", "contrast"})
      if (options.method == RegionMethod::Tips && vm.count(name) && !vm[name].defaulted())
        throw UsageError(std::string("--") + name +
                         " shapes the cap finder's caps; it does not apply with --method tips");
    if (!points.empty()) at = parse_region_points(points);
    OutputPlan plan;
    plan.inputs.push_back({"INPUT", input});
    if (!output.empty()) plan.outputs.push_back({"-o", output});
    if (!face_list.empty()) plan.outputs.push_back({"--face-list", face_list});
    check_planned_outputs(plan);  // none is the input or the other, all writable (output_paths.hpp)
  } catch (const po::error& e) {
    return usage_error("regions", e.what());
  } catch (const UsageError& e) {
    return usage_error("regions", spell_options(e.what(), OptionSpelling::Cli));
  }

  try {
    // Names a stage silent for a second (cli/stage_notice.hpp): a large mesh's search takes
    // seconds. The library's stages (reading, checking, the finder's) begin stages there.
    StageNotice notice(std::cerr, true);
    const ProgressStageScope stages = notice.scope();
    InputReport input_report;
    Mesh mesh = read_input_mesh(input, &input_report);
    notice.end();
    for (const std::string& w : input_report.warnings) std::cerr << "warning: " << w << '\n';
    for (const std::string& n : input_report.notes) std::cerr << "note: " << n << '\n';
    const Positions x = positions_from_mesh(mesh);
    RegionReport report;
    notice.begin(at.empty() ? "selecting the regions"
                            : "growing the regions at the --region-at points");
    if (at.empty()) {
      mark_spherical_regions(mesh, x, options, &report);  // f:region and the curvature maps
    } else {
      store_regions(mesh, select_regions_at(mesh, x, at, options, &report));
      store_curvature(mesh, compute_curvature(mesh, x));
      for (const std::string& w : report.warnings)  // points far from the surface
        std::cerr << "warning: " << spell_options(w, OptionSpelling::Cli) << '\n';
    }
    if (!output.empty()) {
      notice.begin("writing " + output);
      write_region_ply(output, mesh, x);
    }
    if (!face_list.empty()) {
      notice.begin("writing " + face_list);
      try {
        write_region_file(face_list, stored_regions(mesh));
      } catch (const UsageError&) {  // -o is written by now: say so, as `run` lists its outputs
        notice.end();
        if (!output.empty()) notice.line("wrote: " + output);
        throw;
      }
    }
    notice.end();

    ClassicOStringStream out;
    out << "file: " << input << '\n'
        << "faces: " << mesh.number_of_faces() << '\n'
        << "reference_mean_curvature: " << std::setprecision(4) << report.reference_mean_curvature
        << " (area-weighted median |H|)\n"
        << "seeds: " << report.seed_vertices << ", fitted caps: " << report.candidates << '\n'
        << "dropped: " << report.dropped_flat << " flat, " << report.dropped_small << " small, "
        << report.dropped_large << " large, " << report.dropped_shape << " not compact\n"
        << "regions: " << report.regions.size() << '\n';
    out << region_table(report, x);
    if (!output.empty()) out << "wrote: " << output << '\n';
    if (!face_list.empty()) out << "wrote: " << face_list << '\n';
    std::cout << out.str();
    if (stage_times) {
      ClassicOStringStream times;
      for (const RegionStageTime& t : report.stage_times)
        times << "stage " << t.stage << ": wall " << fixed_text(t.wall_s, 3) << " s, cpu "
              << fixed_text(t.cpu_s, 3) << " s\n";
      std::cerr << times.str();
    }
    return static_cast<int>(ExitCode::Success);
  } catch (const InputError& e) {
    std::cerr << "shellcontract regions: " << e.what() << '\n';
    return static_cast<int>(ExitCode::BadInput);
  } catch (const UsageError& e) {  // e.g. the output folder is not writable
    std::cerr << "shellcontract regions: " << e.what() << '\n';
    return static_cast<int>(ExitCode::BadUsage);
  }
}

}  // namespace shellcontract::cli
