// `run --summary`'s JSON (run_summary.hpp).
#include "run_summary.hpp"

#include <sys/resource.h>

#include <charconv>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace shellcontract::cli {
namespace {

/// The library's summary (write_run_summary) into a JSON object.
class JsonSummary final : public SummaryWriter {
 public:
  /// @param more_warnings appended to `warnings` (not copied: it must outlive the writer)
  explicit JsonSummary(JsonObject& o, const std::vector<std::string>* more_warnings = nullptr)
      : o_(o), more_warnings_(more_warnings) {}
  void add_bool(const std::string& key, bool v) override { o_.add(key, v); }
  void add_null(const std::string& key) override { o_.add_raw(key, "null"); }
  void add_integer(const std::string& key, long long v) override {
    o_.add_raw(key, std::to_string(v));
  }
  void add_number(const std::string& key, double v) override { o_.add(key, v); }
  void add_text(const std::string& key, const std::string& v) override { o_.add(key, v); }
  void add_texts(const std::string& key, const std::vector<std::string>& v) override {
    if (key != "warnings" || !more_warnings_ || more_warnings_->empty()) {
      o_.add(key, v);
      return;
    }
    std::vector<std::string> all = v;
    all.insert(all.end(), more_warnings_->begin(), more_warnings_->end());
    o_.add(key, all);
  }
  void add_numbers(const std::string& key, const std::vector<double>& v) override {
    std::string raw = "[";
    for (std::size_t i = 0; i < v.size(); ++i) raw += (i ? ", " : "") + json_number(v[i]);
    o_.add_raw(key, raw + "]");
  }
  void add_object(const std::string& key,
                  const std::function<void(SummaryWriter&)>& fill) override {
    JsonObject inner;
    JsonSummary w(inner);
    fill(w);
    o_.add(key, inner);
  }

 private:
  JsonObject& o_;
  const std::vector<std::string>* more_warnings_;  ///< the CLI's own, after the library's
};

}  // namespace

JsonObject export_json(const FrameExporter& e) {
  const ExportStats f = e.frame_stats();
  JsonObject o;
  o.add("every", e.every())
      .add("frames_written", f.frames_written)
      .add("frame_bytes", static_cast<std::size_t>(f.bytes))
      .add("simulation_thread_seconds", f.caller_seconds + e.gltf_copy_seconds())
      .add("writer_thread_seconds", f.writer_seconds)
      .add("gltf_bytes", e.gltf_bytes())
      .add("gltf_seconds", e.gltf_seconds());
  return o;
}

JsonObject summary_json(const std::string& input, const std::string& output,
                        const InputReport& report, const RunOptions& options, const RunResult& r,
                        std::optional<int> exit_code,
                        const std::vector<std::string>& output_warnings) {
  JsonObject s;
  JsonSummary w(s, &output_warnings);
  const SummaryFiles files{input, output, exit_code};
  write_run_summary(w, report, options, r, OptionSpelling::Cli, &files);
  return s;
}

/// The process's peak resident memory so far. Linux's VmHWM (/proc/self/status, in kB) first:
/// getrusage's ru_maxrss keeps, across exec, the peak of the process that forked this one, so a
/// tool started from a script reported the script's peak, not its own, for a small mesh
/// (tests/cli/test_cli_run_control.cpp). getrusage (KiB on Linux) where /proc is not there.
double peak_memory_mb() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmHWM:", 0) == 0) {
      // "VmHWM:\t  1234 kB": an integer after blanks (from_chars, as every number the tool reads).
      const std::size_t digits = line.find_first_not_of(" \t", 6);
      long long kb = 0;
      if (digits != std::string::npos &&
          std::from_chars(line.data() + digits, line.data() + line.size(), kb).ec == std::errc() &&
          kb > 0)
        return static_cast<double>(kb) / 1024.0;
    }
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;
}

}  // namespace shellcontract::cli
