// The CLI's observers of a run (shellcontract/run.hpp): warnings and progress on stderr, the CSV
// log, the start and end fields. Each has one job; cli/run.cpp picks those the options ask for.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <functional>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

#include "core/decimal_text.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/report.hpp"
#include "shellcontract/run.hpp"
#include "sim/fields.hpp"
#include "sim/frame_access.hpp"
#include "sim/simulator.hpp"
#include "stage_notice.hpp"

namespace shellcontract::cli {

inline FieldColour parse_field_colour(const std::string& s) {
  if (s == "mean") return FieldColour::MeanCurvature;
  if (s == "gaussian") return FieldColour::GaussianCurvature;
  if (s == "pressure") return FieldColour::Pressure;
  if (s == "energy") return FieldColour::EnergyDensity;
  throw UsageError("unknown --fields-colour '" + s +
                   "' (expected mean, gaussian, pressure or energy)");
}

/// "warning: ..." on stderr as the run finds it (through the stage line's lock: a warning of the
/// preparation may come while a stage is current).
class WarningPrinter final : public RunObserver {
 public:
  explicit WarningPrinter(StageNotice& notice) : notice_(notice) {}
  void warning(const std::string& text) override {
    notice_.line("warning: " + spell_options(text, OptionSpelling::Cli));
  }

 private:
  StageNotice& notice_;
};

/// A duration for the progress line: "9.24 s" below a minute, then "5 min 07 s", "2 h 05 min".
inline std::string duration_text(double seconds) {
  if (!(seconds < 59.5)) {
    const long total = std::lround(std::min(seconds, 1e9));
    const auto two = [](long n) { return (n < 10 ? "0" : "") + std::to_string(n); };
    if (total < 3600) return std::to_string(total / 60) + " min " + two(total % 60) + " s";
    return std::to_string(total / 3600) + " h " + two(total % 3600 / 60) + " min";
  }
  return general_text(std::max(seconds, 0.0), 3) + " s";
}

/// The wall time per frame over the last WINDOW frames (and the preparation's end): recent, so
/// that a run whose steps slow down as contacts build up is not read at its early speed.
class FrameRate {
 public:
  static constexpr std::size_t WINDOW = 20;
  /// The frame the loop starts at, and when.
  void start(int frame, std::chrono::steady_clock::time_point t) { marks_.assign(1, {frame, t}); }
  void add(int frame, std::chrono::steady_clock::time_point t) {
    marks_.push_back({frame, t});
    if (marks_.size() > WINDOW + 1) marks_.pop_front();
  }
  /// Seconds per frame over the window; negative before a frame has ended.
  double seconds_per_frame() const {
    if (marks_.size() < 2 || marks_.back().first <= marks_.front().first) return -1.0;
    return std::chrono::duration<double>(marks_.back().second - marks_.front().second).count() /
           (marks_.back().first - marks_.front().first);
  }

 private:
  std::deque<std::pair<int, std::chrono::steady_clock::time_point>> marks_;
};

/// A progress line on stderr about once a second, and at the last frame: the frame, V/V0, the
/// time since the first step, the recent seconds per frame and an estimate of the time left
/// (the frames left at that rate: a run that reaches its target or stop ratio ends sooner).
/// Before the first frame, the stages of the preparation that last a second (StageNotice), a
/// line for the preparation if it took a second or more (bear subdivided three times: about 4 s),
/// and the regions found.
class ProgressPrinter final : public RunObserver {
 public:
  using Clock = std::chrono::steady_clock;
  /// Made just before the run starts preparing. `regions_origin` says where regions the user did
  /// not list came from ("spherical regions selected by curvature"); empty: no line about the
  /// regions. `now`: the clock (a test's own).
  ProgressPrinter(int frames, std::string regions_origin, StageNotice& notice,
                  std::function<Clock::time_point()> now = Clock::now)
      : frames_(frames),
        regions_origin_(std::move(regions_origin)),
        notice_(notice),
        now_(std::move(now)),
        made_(now_()) {}
  void stage(const std::string& what) override { notice_.begin(what); }
  void started(const FrameView& view) override {
    notice_.end();
    start_ = last_ = now_();
    rate_.start(view.frame(), start_);
    const double prepare = std::chrono::duration<double>(start_ - made_).count();
    if (prepare >= 1.0) notice_.line("prepared in " + general_text(prepare, 3) + " s");
    const std::size_t regions = view.regions();
    if (!regions_origin_.empty() && regions > 0)
      notice_.line("regions: " + std::to_string(regions) + " " + regions_origin_);
  }
  void frame(const FrameView& view, const FrameMetrics& m) override {
    notice_.end();  // the last step's check (`validate` end) is over
    const auto now = now_();
    rate_.add(m.frame, now);
    if (std::chrono::duration<double>(now - last_).count() > 1.0 || view.last()) {
      std::string text = "frame " + std::to_string(m.frame) + "/" + std::to_string(frames_) +
                         "  V/V0 " + general_text(m.volume_ratio, 6) + "  " +
                         duration_text(std::chrono::duration<double>(now - start_).count());
      if (const double step = rate_.seconds_per_frame(); step >= 0.0) {
        const int left = view.last() ? 0 : std::max(frames_ - m.frame, 0);
        text += "  " + general_text(step, 3) + " s/frame  ~" + duration_text(left * step) +
                " left (estimate)";
      }
      notice_.line(text);
      last_ = now;
    }
  }
  void finished(const FrameView&, const RunResult&) override { notice_.end(); }

 private:
  int frames_;
  std::string regions_origin_;
  StageNotice& notice_;
  std::function<Clock::time_point()> now_;
  Clock::time_point made_, start_, last_;
  FrameRate rate_;
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
