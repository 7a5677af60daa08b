// bench error's table, CSV, plot script and the plot's temporary file (cli/bench_error.cpp
// runs the ladder; this writes what it found).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "mesh/file_safety.hpp"
#include "sim/error_ladder.hpp"

namespace shellcontract::cli::bench {

/// v with `precision` significant digits, `nan_text` for NaN (a failed run).
std::string fmt(double v, int precision = 3, const char* nan_text = "failed");
/// The rungs as the table on stdout.
void print_rows(const std::vector<ErrorLadderRow>& rows, std::ostream& os);
/// The reference checks as their table on stdout.
void print_checks(const std::vector<ReferenceCheck>& checks, std::ostream& os);
/// The whole result as CSV (bench_error_output.cpp says which rows and columns).
std::string to_csv(const ErrorLadderResult& res);
/// gnuplot commands drawing the CSV `csv` into `out` (.svg or .png) under `title`.
std::string gnuplot_script(const std::string& csv, const std::string& out, const std::string& title,
                           const ErrorLadderResult& res);
/// The folders where the plot's temporary CSV can be written, in order.
/// @throws UsageError when none takes one
std::vector<std::string> temporary_folders();
/// A new temporary file holding `text` in the first of `folders` that takes it whole; fd -1 and
/// `error` set when none does.
RegisteredTemporary temporary_csv(const std::vector<std::string>& folders, const std::string& text,
                                  std::string& error);
/// Whether gnuplot is on PATH.
bool gnuplot_available();

}  // namespace shellcontract::cli::bench
