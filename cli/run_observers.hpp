// The CLI's observers of a run (shellcontract/run.hpp): warnings and progress on stderr, the CSV
// log, the start and end fields. Each has one job; cli/run.cpp picks those the options ask for.
#pragma once

#include <chrono>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

#include "shellcontract/error.hpp"
#include "shellcontract/report.hpp"
#include "shellcontract/run.hpp"
#include "sim/fields.hpp"
#include "sim/frame_access.hpp"
#include "sim/simulator.hpp"

namespace shellcontract::cli {

inline FieldColour parse_field_colour(const std::string& s) {
  if (s == "mean") return FieldColour::MeanCurvature;
  if (s == "gaussian") return FieldColour::GaussianCurvature;
  if (s == "pressure") return FieldColour::Pressure;
  if (s == "energy") return FieldColour::EnergyDensity;
  throw UsageError("unknown --fields-colour '" + s +
                   "' (expected mean, gaussian, pressure or energy)");
}

/// "warning: ..." on stderr as the run finds it.
class WarningPrinter final : public RunObserver {
 public:
  void warning(const std::string& text) override {
    std::cerr << "warning: " << spell_options(text, OptionSpelling::Cli) << '\n';
  }
};

/// A progress line on stderr about once a second, and at the last frame; before the first
/// frame, a line for the preparation (rest state, constraints, collision structures) if it took
/// a second or more (bear subdivided three times: about 4 s).
class ProgressPrinter final : public RunObserver {
 public:
  /// Made just before the run starts preparing. `regions_origin` says where regions the user did
  /// not list came from ("spherical regions selected by curvature"); empty: no line about the regions.
  ProgressPrinter(int frames, std::string regions_origin)
      : frames_(frames), regions_origin_(std::move(regions_origin)), made_(std::chrono::steady_clock::now()) {}
  void started(const FrameView& view) override {
    start_ = last_ = std::chrono::steady_clock::now();
    const double prepare = std::chrono::duration<double>(start_ - made_).count();
    if (prepare >= 1.0)
      std::cerr << "prepared in " << std::setprecision(3) << prepare << " s\n";
    const std::size_t regions = view.regions();
    if (!regions_origin_.empty() && regions > 0)
      std::cerr << "regions: " << regions << " " << regions_origin_ << '\n';
  }
  void frame(const FrameView& view, const FrameMetrics& m) override {
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_).count() > 1.0 || view.last()) {
      std::cerr << "frame " << m.frame << "/" << frames_ << "  V/V0 " << std::setprecision(6)
                << m.volume_ratio << "  " << std::setprecision(3)
                << std::chrono::duration<double>(now - start_).count() << " s\n";
      last_ = now;
    }
  }

 private:
  int frames_;
  std::string regions_origin_;
  std::chrono::steady_clock::time_point made_, start_, last_;
};

/// The per-frame CSV log (README "Outputs"), kept in memory and written at the end.
class CsvLog final : public RunObserver {
 public:
  void frame(const FrameView&, const FrameMetrics& m) override {
    text_ += log_csv_line(log_row(m));
  }
  const std::string& text() const { return text_; }
  /// A resumed run's log so far (its checkpoint's), header included.
  void restore(std::string text) { text_ = std::move(text); }

 private:
  std::string text_ = log_csv_header();
};

/// PREFIX_start.ply at the rest state and PREFIX_end.ply at the end (README "Outputs"). Both
/// are held in memory and written by write() once the run has finished, with its other outputs:
/// an interrupted run (exit 130) writes no fields, as it writes no result (docs/cli.md); a start
/// file written as the run began was left behind by every Ctrl-C.
class FieldsWriter final : public RunObserver {
 public:
  FieldsWriter(std::string prefix, FieldColour colour)
      : prefix_(std::move(prefix)), colour_(colour) {}
  void started(const FrameView& view) override { start_ = take(view); }
  void finished(const FrameView& view, const RunResult& r) override {
    if (r.status != RunStatus::Cancelled) end_ = take(view);
  }
  /// Writes PREFIX_start.ply, then PREFIX_end.ply (each atomically); only after a run that
  /// finished (its end fields taken).
  /// @throws UsageError naming the file that could not be written
  void write() const {
    if (!start_ || !end_) throw UsageError("the run did not finish: no fields to write");
    write_fields_ply(prefix_ + "_start.ply", *start_);
    write_fields_ply(prefix_ + "_end.ply", *end_);
  }

 private:
  FieldsPly take(const FrameView& view) const {
    const Simulator& sim = simulator_of(view);
    return fields_ply(sim, view.positions(), compute_vertex_fields(sim), colour_);
  }
  std::string prefix_;
  FieldColour colour_;
  std::optional<FieldsPly> start_, end_;
};

}  // namespace shellcontract::cli
