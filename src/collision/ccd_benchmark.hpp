// Reading the CCD benchmark queries (Wang et al. 2021 / Belgrod et al. 2023 file format, see
// shared/data/ccd-queries/README.md) and running the narrow phase on them: false positives,
// false negatives and time per query, for one tolerance or a sweep of tolerances.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "collision/ccd.hpp"

namespace shellcontract {

/// One benchmark query: the stencil at t = 0 and t = 1 and the exact answer.
struct CcdQuery {
  CcdStencil x0;       ///< rows 1-4 of the query, in the stencil order of ccd.hpp
  CcdStencil x1;       ///< rows 5-8
  bool truth = false;  ///< true if the primitives touch at some t in [0,1] (exact ground truth)
};

/// All queries of one file.
struct CcdQueryFile {
  std::string path;           ///< as opened
  std::string name;           ///< path relative to the directory searched, e.g. "simulation/edge-edge.csv"
  CcdPrimitive kind = CcdPrimitive::VertexFace;
  std::vector<CcdQuery> queries;
};

/// The primitive type of a query file from its name: "vertex-face.csv" or "edge-edge.csv"
/// (the file name may carry a prefix, e.g. "x-vertex-face.csv").
/// @param path  file path
/// @param kind  set on success
/// @return false if the name matches neither
bool ccd_query_kind_from_name(const std::string& path, CcdPrimitive& kind);

/// The query files under a directory, recursively: every regular file ending in ".csv" except
/// "*.index.csv", sorted by path so runs are reproducible.
/// @param dir  directory to search
/// @return paths (possibly empty)
/// @throws UsageError if dir does not exist or is not a directory
std::vector<std::string> find_ccd_query_files(const std::string& dir);

/// Reads one query file. Each row is x_num,x_den,y_num,y_den,z_num,z_den,truth (7 integers);
/// 8 rows form one query. Numerators and denominators are parsed with strtod, which is exact for
/// the data (numerators below 2^53, denominators powers of two up to 2^111), and num/den is then
/// the exact double coordinate. Empty lines are ignored.
/// @param path  the .csv file
/// @param name  name to record (default: the path)
/// @return the queries; the type comes from the file name
/// @throws InputError naming the file and line if the file cannot be read, a row is malformed
///         (field count, non-numeric field, zero denominator, non-finite value, truth not 0/1,
///         truth differing inside a query), the row count is not a multiple of 8, or the file
///         name does not give the type
CcdQueryFile read_ccd_query_file(const std::string& path, const std::string& name = "");

/// Results of one file at one tolerance.
struct CcdBenchmarkRow {
  std::string file;              ///< CcdQueryFile::name
  CcdPrimitive kind = CcdPrimitive::VertexFace;
  double tolerance = 0.0;        ///< tau used, in the file's coordinate units
  std::size_t queries = 0;
  std::size_t positives = 0;     ///< queries whose truth is 1
  std::size_t false_positives = 0;
  std::size_t false_negatives = 0;
  std::size_t uncertain_hits = 0;  ///< hits with CcdResult::certain == false
  double mean_us = 0.0;            ///< mean of the queries' times, microseconds (run_ccd_benchmark)
  double max_us = 0.0;             ///< largest of the same times, microseconds; >= mean_us
  std::vector<std::size_t> false_negative_ids;  ///< 0-based query numbers of the misses
  std::vector<std::size_t> false_positive_ids;  ///< 0-based query numbers of the false alarms
};

/// Default number of timing repetitions of run_ccd_benchmark.
static constexpr int DEFAULT_CCD_BENCHMARK_REPETITIONS = 3;

/// Runs the narrow phase on every query of a file, single-threaded: one untimed pass (the
/// answers; it also warms the caches), then `repetitions` passes timing each query alone. A
/// query's time is its fastest run, which filters out interference from other processes on a
/// shared machine; mean_us and max_us are the mean and the largest of these times, so
/// max_us >= mean_us, and both include the clock's own overhead (lab/history.md). Every pass
/// must give the same answers (the test is deterministic).
/// @param file         queries
/// @param options      CCD options (tolerance in the file's units)
/// @param repetitions  timing repetitions, >= 1 (values below 1 count as 1)
/// @return counts and times
/// @throws std::logic_error if two passes disagree
CcdBenchmarkRow run_ccd_benchmark(const CcdQueryFile& file, const CcdOptions& options,
                                  int repetitions = DEFAULT_CCD_BENCHMARK_REPETITIONS);

/// Sets row.mean_us and row.max_us to the mean and the largest of per-query times (microseconds;
/// 0 for no query). The mean is never above the largest, which the rounded sum could push it to.
/// @param row       the row whose times are set
/// @param times_us  one time per query
void set_ccd_query_times(CcdBenchmarkRow& row, const std::vector<double>& times_us);

/// Speed-against-error table: run_ccd_benchmark for each file at each tolerance, tolerances in
/// the outer loop.
/// @param files       queries
/// @param tolerances  list of tau values (file units)
/// @param base        the other options
/// @param repetitions  timing repetitions (see run_ccd_benchmark)
/// @return one row per (tolerance, file)
std::vector<CcdBenchmarkRow> run_ccd_tolerance_sweep(
    const std::vector<CcdQueryFile>& files, const std::vector<double>& tolerances,
    const CcdOptions& base = {}, int repetitions = DEFAULT_CCD_BENCHMARK_REPETITIONS);

}  // namespace shellcontract
