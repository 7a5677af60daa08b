// CCD benchmark files: reader and runner (shared/data/ccd-queries/README.md, "Format").
#include "collision/ccd_benchmark.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "core/decimal_text.hpp"
#include "shellcontract/error.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

[[noreturn]] void fail(const std::string& path, std::size_t line, const std::string& what) {
  throw InputError(path + ":" + std::to_string(line) + ": " + what);
}

/// Parses one integer-valued field as strtod in the "C" locale (parse_c_number); the whole field
/// (after trimming blanks) must be consumed.
double parse_field(const std::string& s, std::size_t begin, std::size_t end, const std::string& path,
                   std::size_t line, int column) {
  while (begin < end && (s[begin] == ' ' || s[begin] == '\t')) ++begin;
  while (end > begin && (s[end - 1] == ' ' || s[end - 1] == '\t' || s[end - 1] == '\r')) --end;
  const std::string field = s.substr(begin, end - begin);
  if (field.empty()) fail(path, line, "empty field " + std::to_string(column));
  double v = 0.0;
  if (!parse_c_number(field, v))
    fail(path, line, "field " + std::to_string(column) + " is not a number: '" + field + "'");
  if (!std::isfinite(v)) fail(path, line, "field " + std::to_string(column) + " is not finite");
  return v;
}

}  // namespace

bool ccd_query_kind_from_name(const std::string& path, CcdPrimitive& kind) {
  const std::string name = fs::path(path).filename().string();
  if (ends_with(name, "vertex-face.csv")) {
    kind = CcdPrimitive::VertexFace;
    return true;
  }
  if (ends_with(name, "edge-edge.csv")) {
    kind = CcdPrimitive::EdgeEdge;
    return true;
  }
  return false;
}

std::vector<std::string> find_ccd_query_files(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw UsageError("not a directory: '" + dir + "'");
  std::vector<std::string> out;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (!it->is_regular_file(ec)) continue;
    const std::string name = it->path().filename().string();
    if (ends_with(name, ".csv") && !ends_with(name, ".index.csv")) out.push_back(it->path().string());
  }
  if (ec) throw UsageError("cannot list '" + dir + "': " + ec.message());
  std::sort(out.begin(), out.end());
  return out;
}

CcdQueryFile read_ccd_query_file(const std::string& path, const std::string& name) {
  CcdQueryFile file;
  file.path = path;
  file.name = name.empty() ? path : name;
  if (!ccd_query_kind_from_name(path, file.kind))
    fail(path, 0, "file name gives no query type (expected vertex-face.csv or edge-edge.csv)");
  std::ifstream in(path);
  if (!in) fail(path, 0, "cannot open for reading");
  std::string s;
  std::size_t line = 0, row = 0;
  CcdQuery q;
  int truth = -1;
  while (std::getline(in, s)) {
    ++line;
    if (s.find_first_not_of(" \t\r") == std::string::npos) continue;
    double v[7];
    std::size_t begin = 0;
    int col = 0;
    for (;; ++col) {
      const std::size_t comma = s.find(',', begin);
      const std::size_t end = comma == std::string::npos ? s.size() : comma;
      if (col >= 7) fail(path, line, "more than 7 fields");
      v[col] = parse_field(s, begin, end, path, line, col + 1);
      if (comma == std::string::npos) break;
      begin = comma + 1;
    }
    if (col != 6) fail(path, line, "expected 7 fields, found " + std::to_string(col + 1));
    Vec3 p;
    for (int k = 0; k < 3; ++k) {
      const double den = v[2 * k + 1];
      if (den == 0.0) fail(path, line, "zero denominator in field " + std::to_string(2 * k + 2));
      p[k] = v[2 * k] / den;
      if (!std::isfinite(p[k])) fail(path, line, "coordinate is not finite");
    }
    if (v[6] != 0.0 && v[6] != 1.0) fail(path, line, "truth must be 0 or 1");
    const int t = v[6] == 1.0 ? 1 : 0;
    const std::size_t k = row % 8;
    if (k == 0) truth = t;
    else if (t != truth) fail(path, line, "truth differs from the query's first row");
    (k < 4 ? q.x0[k] : q.x1[k - 4]) = p;
    if (k == 7) {
      q.truth = truth == 1;
      file.queries.push_back(q);
    }
    ++row;
  }
  if (in.bad()) fail(path, line, "read error");
  if (row % 8 != 0)
    fail(path, line, std::to_string(row) + " data rows is not a multiple of 8 (8 rows per query)");
  return file;
}

void set_ccd_query_times(CcdBenchmarkRow& row, const std::vector<double>& times_us) {
  double sum = 0.0, most = 0.0;
  for (const double t : times_us) {
    sum += t;
    most = std::max(most, t);
  }
  row.max_us = most;
  // The rounded sum can exceed n times the largest time (three times 0.1 sum to more than 0.3);
  // the mean of the same times is never above their maximum.
  row.mean_us = times_us.empty() ? 0.0 : std::min(sum / static_cast<double>(times_us.size()), most);
}

CcdBenchmarkRow run_ccd_benchmark(const CcdQueryFile& file, const CcdOptions& options,
                                  int repetitions) {
  using Clock = std::chrono::steady_clock;
  const int reps = std::max(1, repetitions);
  const std::size_t n = file.queries.size();
  CcdBenchmarkRow row;
  row.file = file.name;
  row.kind = file.kind;
  row.tolerance = options.tolerance;
  row.queries = n;
  std::vector<char> hits(n, 0), certain(n, 0);
  auto check = [&](std::size_t i, const CcdResult& r) {
    if (r.hit != static_cast<bool>(hits[i]))
      throw std::logic_error("CCD is not deterministic on " + file.name + " query " + std::to_string(i));
  };

  // One untimed pass for the answers. It also brings the code and the queries into the caches:
  // before, the mean came from whole passes, the first of them cold, and the maximum from each
  // query timed alone afterwards, so that a single repetition reported a mean above the maximum.
  for (std::size_t i = 0; i < n; ++i) {
    const CcdQuery& q = file.queries[i];
    const CcdResult r = primitive_ccd(file.kind, q.x0, q.x1, options);
    hits[i] = r.hit;
    certain[i] = r.certain;
  }
  // `reps` passes, each query timed alone, its fastest run kept: the mean and the maximum are of
  // these same times (both include the clock's own overhead).
  std::vector<double> fastest_us(n, std::numeric_limits<double>::infinity());
  for (int rep = 0; rep < reps; ++rep) {
    for (std::size_t i = 0; i < n; ++i) {
      const CcdQuery& q = file.queries[i];
      const auto a = Clock::now();
      const CcdResult r = primitive_ccd(file.kind, q.x0, q.x1, options);
      const auto b = Clock::now();
      fastest_us[i] =
          std::min(fastest_us[i], std::chrono::duration<double, std::micro>(b - a).count());
      check(i, r);
    }
  }
  set_ccd_query_times(row, fastest_us);

  for (std::size_t i = 0; i < n; ++i) {
    const bool truth = file.queries[i].truth;
    row.positives += truth;
    if (hits[i] && !certain[i]) ++row.uncertain_hits;
    if (hits[i] && !truth) {
      ++row.false_positives;
      row.false_positive_ids.push_back(i);
    }
    if (!hits[i] && truth) {
      ++row.false_negatives;
      row.false_negative_ids.push_back(i);
    }
  }
  return row;
}

std::vector<CcdBenchmarkRow> run_ccd_tolerance_sweep(const std::vector<CcdQueryFile>& files,
                                                     const std::vector<double>& tolerances,
                                                     const CcdOptions& base, int repetitions) {
  std::vector<CcdBenchmarkRow> rows;
  for (double tau : tolerances) {
    CcdOptions opt = base;
    opt.tolerance = tau;
    for (const CcdQueryFile& f : files) rows.push_back(run_ccd_benchmark(f, opt, repetitions));
  }
  return rows;
}

}  // namespace shellcontract
