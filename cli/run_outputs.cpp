// run's files after the run (run_steps.hpp): each output written on its own, the summary last,
// and the words and exit code the run ends with. A finished result is never thrown away: an
// output that fails (a full disk) is reported and the others are still written
// (output-safety.md).
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "command_line.hpp"
#include "core/plural.hpp"
#include "json_writer.hpp"
#include "mesh/float32_positions.hpp"
#include "run_failure.hpp"
#include "run_precision.hpp"
#include "run_steps.hpp"
#include "run_summary.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "sim/checkpoint.hpp"

namespace shellcontract::cli {
namespace {

/// The --summary document: the library's summary of the run with what only the CLI knows (the
/// setup's times, the repair, the exports) and how the other outputs went. An output that
/// failed makes the process exit 1 (or the run's own failure code), and the summary says so.
/// The input file's identity, so that a summary names the bytes it was run on, not only a path
/// that may since hold another file: its absolute path, its size and its 64-bit FNV-1a (the
/// checkpoint's fnv1a, sim/checkpoint.hpp, from the standard offset basis). Empty where it cannot
/// be read again (it was read for the run).
JsonObject input_identity(const std::string& path) {
  JsonObject o;
  std::ifstream in(path, std::ios::binary);
  if (!in) return o;
  // FNV-1a's published offset basis: the checkpoint's own default differs (a digit short), which
  // is harmless for its checksums but would not be the hash a reader computes with another tool.
  std::uint64_t hash = 14695981039346656037ull;
  std::uint64_t bytes = 0;
  std::vector<char> chunk(1 << 16);
  while (in.read(chunk.data(), static_cast<std::streamsize>(chunk.size())) || in.gcount() > 0) {
    const auto n = static_cast<std::size_t>(in.gcount());
    hash = fnv1a(chunk.data(), n, hash);
    bytes += n;
  }
  if (in.bad()) return o;
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(hash));
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(path, ec);
  o.add("path", ec ? path : absolute.string())
      .add("bytes", static_cast<std::size_t>(bytes))
      .add("fnv1a64", std::string(hex));
  return o;
}

JsonObject run_summary(const RunRequest& request, const RunInputMesh& input, const RunResult& r,
                       const RunObservers& observers, const OutputWriter& writer) {
  const OutputStatus& outputs = writer.outputs;
  JsonObject summary = summary_json(
      request.input, request.output, input.report, request.options, r,
      outputs.failed() ? std::optional<int>(output_failure_exit_code(r)) : std::nullopt,
      writer.warnings());
  JsonObject setup;
  setup.add("read_and_check_seconds", input.read_seconds)
      .add("read_seconds", input.report.read_seconds)
      .add("check_seconds", input.report.check_seconds)
      .add("regions_seconds", r.regions_seconds)
      .add("prepare_seconds", r.prepare_seconds);
  summary.add("input_file", input_identity(request.input));
  summary.add("setup", setup).add("peak_memory_mb", peak_memory_mb());
  if (request.repair) {
    const RepairReport& repair = input.repair_report;
    JsonObject rep;
    rep.add("already_usable", repair.already_usable)
        .add("input_problem", repair.input_problem)
        .add("changes", repair.summary_lines());
    summary.add("repair", rep);
  }
  if (!request.exports.dir.empty() || !request.exports.gltf.empty())
    summary.add("export", export_json(observers.exporter));
  summary.add("outputs", outputs.json());
  return summary;
}

}  // namespace

void OutputWriter::attempt(const char* option, const std::string& path,
                           const std::function<void()>& write) {
  trace_.stage = "writing " + path;
  notice_.begin(trace_.stage);
  const auto failed = [&](const std::string& why) {
    std::error_code ec;  // a file there before the run is left as it was
    outputs.add(
        option, path,
        (std::filesystem::exists(path, ec) ? "failed, the old file kept: " : "failed: ") + why);
  };
  try {
    write();
    trace_.written = trace_.written.empty() ? path : trace_.written + " and " + path;
    outputs.add(option, path, "written");
  } catch (const UsageError& e) {
    failed(e.what());
  } catch (const std::invalid_argument& e) {
    // A state the writer refuses (not finite): this output's failure, not std::terminate.
    failed(e.what());
  }
  notice_.end();
}

void OutputWriter::warn_once(const std::string& warning) {
  if (!warned_.insert(warning).second) return;
  std::cerr << "warning: " << warning << '\n';
  said_.push_back(warning);
}

void write_run_outputs(OutputWriter& writer, const RunRequest& request, const RunInputMesh& input,
                       const std::shared_ptr<const MeshDocument>& document, const RunResult& r,
                       RunObservers& observers) {
  const ExportRequest& exports = request.exports;
  FrameExporter& exporter = observers.exporter;
  OutputStatus& outputs = writer.outputs;
  // A checkpoint that could not be saved is no failed output (the run went on without it,
  // its result is whole) but the summary says so: a pipeline relying on it must learn.
  const CliCheckpointer& checkpointer = *observers.checkpointer;
  if (!checkpointer.failure_report().empty())
    outputs.note("--checkpoint", request.checkpoint_path, checkpointer.failure_report());
  if (!exporter.export_error().empty()) {
    std::cerr << "warning: the frame export stopped: " << exporter.export_error() << '\n';
    outputs.add("--export-dir", exports.dir,
                std::to_string(exporter.frame_stats().frames_written) +
                    " frames written, then failed: " + exporter.export_error());
  } else if (!exports.dir.empty()) {
    const auto frames = static_cast<std::size_t>(exporter.frame_stats().frames_written);
    outputs.add("--export-dir", exports.dir,
                "written (" + counted(frames, "frame", "frames") + ")");
  }
  for (const std::string& w : exporter.frame_warnings()) writer.warn_once(w);
  if (!exports.gltf.empty()) writer.attempt("--gltf", exports.gltf, [&] { exporter.write_gltf(); });
  const std::string& output = request.output;
  const Mesh& mesh = input.mesh;
  writer.attempt("-o", output, [&] {
    if (document && document->format() == lower_extension(output)) {
      std::vector<std::string> doc_warnings;  // a material library that does not exist
      // A float32 PLY too coarse for the contacts is written with double x, y, z (a warning).
      const double gap = contact_gap(r.contact_distance, r.normalization_scale);
      write_text_atomic(output,
                        text_keeping_gap(*document, output, input_positions(mesh, r.positions), gap,
                                         &doc_warnings));
      for (const std::string& w : doc_warnings) writer.warn_once(w);
    } else {
      write_mesh_atomic(output, mesh, r.positions);
    }
  });
  if (!request.fields_prefix.empty())
    writer.attempt("--fields", request.fields_prefix + "_*.ply", [&] { observers.fields.write(); });
  const std::string& log_path = request.log_path;
  if (!log_path.empty())
    writer.attempt("--log", log_path, [&] { write_text_atomic(log_path, observers.csv.text()); });
  // The summary is written last, naming how the others went (its own failure is reported on
  // stderr only).
  const std::string& summary_path = request.summary_path;
  if (!summary_path.empty()) {
    const JsonObject summary = run_summary(request, input, r, observers, writer);
    writer.attempt("--summary", summary_path,
                   [&] { write_text_atomic(summary_path, summary.str() + "\n"); });
  }
}

int report_run_end(const RunRequest& request, const RunResult& r, const OutputStatus& outputs) {
  const std::string& output = request.output;
  if (outputs.failed()) {
    std::cerr << "shellcontract run: not every output could be written (the run itself ended: "
              << status_name(r.status) << ", frame " << r.frames_run << ")\n"
              << outputs.text();
    // The run's own failure too (out of memory, a blow-up, validation): the list names only
    // its status, and the exit code is the failure's (output_failure_exit_code).
    const std::string why = run_failure_text(r);
    if (!why.empty()) std::cerr << "shellcontract run: " << why << '\n';
    return output_failure_exit_code(r);
  }
  switch (r.status) {
    case RunStatus::NewIntersections:
      std::cerr << "shellcontract run: validation found new self-intersections: " << r.message
                << '\n';
      break;
    case RunStatus::SimulationFailed:
      std::cerr << "shellcontract run: simulation failed: " << r.message
                << "\nthe last good state (frame " << r.frames_run << ") was written to " << output
                << '\n';
      break;
    case RunStatus::TargetNotReached:
      std::cerr << "warning: " << r.message << "\nthe result (frame " << r.frames_run << ", V/V0 "
                << r.final_volume_ratio << ") was written to " << output << '\n';
      break;
    default:
      // A check that passed says so too: its verdict was in the exit code and the summary only.
      if (!request.quiet)
        std::cerr << "wrote " << output << ": " << r.frames_run
                  << " frames, V/V0 = " << r.final_volume_ratio
                  << (r.new_intersections == 0 ? ", no new self-intersections (--validate)" : "")
                  << '\n';
  }
  return r.exit_code();
}

}  // namespace shellcontract::cli
