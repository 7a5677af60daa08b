// bench error's table, CSV, plot script and gnuplot's run (cli/bench_error.cpp runs the ladder;
// this writes what it found).
#pragma once

#include <ostream>
#include <string>
#include <vector>

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
/// gnuplot commands drawing the CSV text `csv` (to_csv, held in the script) under `title` as
/// SVG (else PNG) on gnuplot's stdout; the script names no file.
std::string gnuplot_script(const std::string& csv, bool svg, const std::string& title,
                           const ErrorLadderResult& res);
/// `text` as a gnuplot single-quoted string: control bytes as printable() writes them, each '
/// doubled, so gnuplot reads it as that one string whatever it holds.
std::string gnuplot_quoted(const std::string& text);
/// Runs gnuplot (found on PATH) on `script` and writes what it draws on its stdout into `out`.
/// @throws UsageError when gnuplot cannot be started, fails (exits other than 0, is killed) or
///         draws nothing; `out` may then hold part of a plot, for the caller to discard
void draw_with_gnuplot(const std::string& script, std::ostream& out);
/// Whether gnuplot is on PATH.
bool gnuplot_available();

}  // namespace shellcontract::cli::bench
