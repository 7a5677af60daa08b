// What a run reports, written once for every front end: the summary's keys and values (the CLI's
// --summary JSON, Python's summary dict) and the log's columns (the CLI's --log CSV, Python's log
// arrays). A front end supplies the container (SummaryWriter); the keys, their order and their
// values are decided here.
#pragma once

#include <array>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "shellcontract/options.hpp"

namespace shellcontract {

struct FrameMetrics;  // sim/simulator.hpp
struct InputReport;   // shellcontract/mesh_io.hpp
struct RunResult;     // shellcontract/run.hpp

/// The log's columns in order (the CSV header, Python's log keys) and which hold integers.
inline constexpr std::size_t LOG_COLUMN_COUNT = 15;
inline constexpr std::array<const char*, LOG_COLUMN_COUNT> LOG_COLUMNS = {
    "frame",          "time",     "volume_ratio", "energy_membrane", "energy_bending",
    "energy_anisotropic", "max_displacement", "step_ms", "solve_ms", "ccd_ms",
    "candidates",     "contacts", "collision_rounds", "failsafe_vertices", "new_intersections"};
inline constexpr std::array<bool, LOG_COLUMN_COUNT> LOG_INTEGER = {
    true, false, false, false, false, false, false, false, false, false, true, true, true, true, true};

/// One log row; the integer columns hold whole numbers (exact below 2^53).
using LogRow = std::array<double, LOG_COLUMN_COUNT>;

/// The log row of one step.
LogRow log_row(const FrameMetrics& m);

/// The CSV header line (with its newline).
std::string log_csv_header();

/// One CSV line (with its newline): every value with 17 significant digits, so that it reads
/// back as the same double; a whole number prints without a decimal point.
std::string log_csv_line(const LogRow& row);

/// The rows of a log written by log_csv_header and log_csv_line (a checkpoint's log), read back
/// to the same doubles whatever locale a host program has set: every line after the header
/// must hold exactly LOG_COLUMN_COUNT numbers.
/// @param name  how a message names the text ("the checkpoint's log")
/// @throws InputError naming the line and the field that is not a number
std::vector<LogRow> log_csv_rows(const std::string& text, const std::string& name);

/// The container a front end gives write_run_summary: a JSON object, a Python dict.
class SummaryWriter {
 public:
  virtual ~SummaryWriter() = default;
  virtual void add_bool(const std::string& key, bool value) = 0;
  /// A key without a value (JSON null, Python None). The default writes a NaN number, which the
  /// CLI's JSON writes as null too.
  virtual void add_null(const std::string& key) {
    add_number(key, std::numeric_limits<double>::quiet_NaN());
  }
  virtual void add_integer(const std::string& key, long long value) = 0;
  virtual void add_number(const std::string& key, double value) = 0;
  virtual void add_text(const std::string& key, const std::string& value) = 0;
  virtual void add_texts(const std::string& key, const std::vector<std::string>& values) = 0;
  /// A list of numbers. The default writes an object keyed "0", "1", ...; the CLI's JSON and
  /// Python's dict write a list.
  virtual void add_numbers(const std::string& key, const std::vector<double>& values) {
    add_object(key, [&values](SummaryWriter& w) {
      for (std::size_t i = 0; i < values.size(); ++i) w.add_number(std::to_string(i), values[i]);
    });
  }
  /// A nested object whose fields `fill` writes into the writer it is given.
  virtual void add_object(const std::string& key,
                          const std::function<void(SummaryWriter&)>& fill) = 0;
};

/// The input and output files, for a summary that names them (the CLI's).
struct SummaryFiles {
  std::string input, output;
  /// The process's exit code where the front end's own outputs change it (an output that could
  /// not be written: exit 1); the run's (RunResult::exit_code) when not set.
  std::optional<int> exit_code;
};

/// Writes the run's summary: status, input, options (each table option under its name in
/// `spelling`, its value as the table prints it), result, totals per step (table2) and every
/// warning (the input's, then the run's; option fields spelled as `spelling` spells them).
/// @param options  the options as resolved (resolve_run_options)
/// @param files    the files to name after exit_code, or nullptr
void write_run_summary(SummaryWriter& w, const InputReport& report, const RunOptions& options,
                       const RunResult& result, OptionSpelling spelling,
                       const SummaryFiles* files = nullptr);

}  // namespace shellcontract
