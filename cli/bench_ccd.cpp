// shellcontract bench ccd: the CCD narrow phase against benchmark queries with exact ground truth
// (../shared/data/ccd-queries/README.md): false positives, false negatives and time per query for
// each file, at one tolerance or a sweep of tolerances (the speed-against-error table).
//
// Exit codes: 0 success, 1 bad usage (unknown option, missing or non-directory --queries, bad
// tolerance list, unwritable --json), 2 unreadable or malformed query file (the message names the
// file and line).
#include <algorithm>
#include <boost/program_options.hpp>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "collision/ccd_benchmark.hpp"
#include "command_line.hpp"
#include "commands.hpp"
#include "core/classic_locale.hpp"
#include "core/decimal_text.hpp"
#include "core/list_text.hpp"
#include "json_writer.hpp"
#include "output_paths.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"

namespace po = boost::program_options;

namespace shellcontract::cli {
namespace {

/// Parses "1e-6,1e-9,0" into numbers >= 0: a list as every list option takes one
/// (core/list_text.hpp), each tolerance once.
std::vector<double> parse_tolerances(const std::string& list) {
  std::vector<std::string> items;
  std::string why;
  if (!split_list(list, items, why)) throw UsageError("--sweep: '" + list + "': " + why);
  std::vector<double> out;
  for (const std::string& item : items) {
    double v = 0.0;
    if (!parse_decimal(item, v) || !(v >= 0.0) || !std::isfinite(v))
      throw UsageError("--sweep: '" + item + "' is not a finite number >= 0");
    if (std::find(out.begin(), out.end(), v) != out.end())
      throw UsageError("--sweep: the tolerance " + item + " is given twice");
    out.push_back(v);
  }
  return out;
}

const char* kind_name(CcdPrimitive k) {
  return k == CcdPrimitive::VertexFace ? "vertex-face" : "edge-edge";
}

void print_table(const std::vector<CcdBenchmarkRow>& rows, std::ostream& os) {
  os << std::left << std::setw(12) << "tolerance" << std::setw(34) << "file" << std::right
     << std::setw(8) << "queries" << std::setw(7) << "pos" << std::setw(6) << "FP" << std::setw(6)
     << "FN" << std::setw(11) << "uncertain" << std::setw(12) << "mean_us" << std::setw(12)
     << "max_us" << '\n';
  for (const CcdBenchmarkRow& r : rows) {
    ClassicOStringStream tol;
    tol << std::setprecision(3) << r.tolerance;
    os << std::left << std::setw(12) << tol.str() << std::setw(34) << r.file << std::right
       << std::setw(8) << r.queries << std::setw(7) << r.positives << std::setw(6)
       << r.false_positives << std::setw(6) << r.false_negatives << std::setw(11)
       << r.uncertain_hits << std::setw(12) << std::fixed << std::setprecision(3) << r.mean_us
       << std::setw(12) << r.max_us << '\n';
    os.unsetf(std::ios::fixed);
  }
}

std::string ids_json(const std::vector<std::size_t>& ids) {
  std::string s = "[";
  for (std::size_t i = 0; i < ids.size(); ++i) s += (i ? ", " : "") + std::to_string(ids[i]);
  return s + "]";
}

std::string rows_json(const std::string& dir, const CcdOptions& opt, int repeat,
                      const std::vector<CcdBenchmarkRow>& rows) {
  std::string arr = "[";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CcdBenchmarkRow& r = rows[i];
    JsonObject o;
    o.add("file", r.file)
        .add("type", kind_name(r.kind))
        .add("tolerance", r.tolerance)
        .add("queries", r.queries)
        .add("positives", r.positives)
        .add("false_positives", r.false_positives)
        .add("false_negatives", r.false_negatives)
        .add("uncertain_hits", r.uncertain_hits)
        .add("mean_us", r.mean_us)
        .add("max_us", r.max_us)
        .add_raw("false_negative_ids", ids_json(r.false_negative_ids))
        .add_raw("false_positive_ids", ids_json(r.false_positive_ids));
    arr += (i ? ",\n    " : "\n    ") + o.str(2);
  }
  arr += rows.empty() ? "]" : "\n  ]";
  JsonObject top;
  top.add("command", "bench ccd")
      .add("queries_dir", dir)
      .add("max_depth", opt.max_depth)
      .add("max_intervals", opt.max_intervals)
      .add("threads", 1)
      .add("repetitions", repeat)
      .add_raw("results", arr);
  return top.str() + "\n";
}

}  // namespace

int command_bench_ccd(int argc, char** argv) {
  std::string dir, json_path, sweep;
  CcdOptions opt;
  std::string tolerance = shortest_text(opt.tolerance);
  int repeat = DEFAULT_CCD_BENCHMARK_REPETITIONS;
  po::options_description desc(
      "usage: shellcontract bench ccd --queries DIR [options]\n\n"
      "Runs the CCD narrow phase on every query file under DIR (recursively: *.csv except\n"
      "*.index.csv; the type comes from the name, vertex-face.csv or edge-edge.csv; format in\n"
      "../shared/data/ccd-queries/README.md, beside the repository) and prints, per file, the\n"
      "false positives (FP), false negatives (FN), hits that floating point could not confirm\n"
      "(uncertain), and the mean and maximum wall time per query (single thread): after one\n"
      "untimed pass, each query is timed alone in --repeat passes and its fastest time kept;\n"
      "mean_us and max_us are the mean and the largest of these times. Lengths are in the\n"
      "files' units.\n\n"
      "exit codes: 0 success, 1 bad usage, 2 unreadable or malformed query file, 3 memory ran\n"
      "            out or the system refused a resource, 130 interrupted\n\noptions");
  desc.add_options()("help,h", "print this help")("queries", po::value<std::string>(&dir),
                                                  "directory of query files (required)")(
      "json", po::value<std::string>(&json_path),
      "also write the results as JSON to this file (written atomically)")(
      "tolerance", po::value<std::string>(&tolerance)->default_value(tolerance),
      "minimum separation tau: a pair closer than tau at some t counts as a collision")(
      "sweep", po::value<std::string>(&sweep),
      "comma-separated list of tolerances, e.g. 0,1e-9,1e-6 (overrides --tolerance)")(
      "max-depth", po::value<int>(&opt.max_depth)->default_value(DEFAULT_CCD_MAX_DEPTH),
      "deepest bisection level of the time step")(
      "max-intervals", po::value<int>(&opt.max_intervals)->default_value(DEFAULT_CCD_MAX_INTERVALS),
      "time intervals examined per query before a conservative hit is reported")(
      "repeat", po::value<int>(&repeat)->default_value(DEFAULT_CCD_BENCHMARK_REPETITIONS),
      "timed passes after the untimed one; each query's fastest time is kept (filters out "
      "other processes)");

  try {
    // Parsed as every command is (command_line.hpp): a stray argument (a second tolerance after
    // --tolerance, a forgotten --sweep) is refused, not dropped.
    const po::variables_map vm = parse_options_only(argc, argv, desc);
    if (vm.count("help")) {
      std::cout << desc << '\n';
      return static_cast<int>(ExitCode::Success);
    }
    if (dir.empty()) throw UsageError("--queries DIR is required");
    // Read as --sweep's items are (Boost's double took "1e-400" as 0 and "inf" as a number).
    if (!parse_decimal(tolerance, opt.tolerance) || !(opt.tolerance >= 0.0) ||
        !std::isfinite(opt.tolerance))
      throw UsageError("--tolerance: '" + tolerance + "' is not a finite number >= 0");
    if (opt.max_depth < 1 || opt.max_depth > 60) throw UsageError("--max-depth must be in 1..60");
    if (opt.max_intervals < 1) throw UsageError("--max-intervals must be >= 1");
    if (repeat < 1) throw UsageError("--repeat must be >= 1");
    const std::vector<double> tolerances =
        sweep.empty() ? std::vector<double>{opt.tolerance} : parse_tolerances(sweep);

    const std::vector<std::string> paths = find_ccd_query_files(dir);
    if (paths.empty()) throw UsageError("no query files (*.csv) under '" + dir + "'");
    // --json may be none of the query files and must be writable, checked before the (long)
    // benchmark: docs/design/output-safety.md.
    if (!json_path.empty()) {
      OutputPlan plan;
      plan.outputs.push_back({"--json", json_path});
      for (const std::string& p : paths) plan.inputs.push_back({"--queries", p});
      check_planned_outputs(plan);
    }
    std::vector<CcdQueryFile> files;
    for (const std::string& p : paths) {
      const std::string name =
          std::filesystem::relative(std::filesystem::path(p), std::filesystem::path(dir)).generic_string();
      files.push_back(read_ccd_query_file(p, name));
    }

    const std::vector<CcdBenchmarkRow> rows = run_ccd_tolerance_sweep(files, tolerances, opt, repeat);
    print_table(rows, std::cout);
    if (!json_path.empty()) write_text_atomic(json_path, rows_json(dir, opt, repeat, rows));
    return static_cast<int>(ExitCode::Success);
  } catch (const po::error& e) {
    return usage_error("bench ccd", e.what());
  } catch (const UsageError& e) {
    return usage_error("bench ccd", e.what());
  } catch (const InputError& e) {
    std::cerr << "shellcontract bench ccd: " << e.what() << '\n';
    return static_cast<int>(ExitCode::BadInput);
  }
}

}  // namespace shellcontract::cli
