// The summary `run --summary` writes: the library's run summary (write_run_summary) as JSON,
// with what only the CLI knows (its exports, the process's peak memory).
#pragma once

#include <optional>
#include <string>

#include "export_observer.hpp"
#include "json_writer.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/report.hpp"
#include "shellcontract/run.hpp"

namespace shellcontract::cli {

/// The frame and glTF exports' counts and times.
JsonObject export_json(const FrameExporter& e);

/// The library's summary of a finished run, with the input and output files named, and the
/// process's exit code where it is not the run's (exit_code). `output_warnings` (what writing
/// the outputs warned of) follow the input's and the run's in `warnings`.
JsonObject summary_json(const std::string& input, const std::string& output,
                        const InputReport& report, const RunOptions& options, const RunResult& r,
                        std::optional<int> exit_code = std::nullopt,
                        const std::vector<std::string>& output_warnings = {});

/// The process's peak resident memory so far, in MiB.
double peak_memory_mb();

}  // namespace shellcontract::cli
