// run's progress on stderr (cli/run_observers.hpp, cli/stage_notice.hpp): the stages the run
// names to its observer (RunObserver::stage, core/progress_stage.hpp) in their order, the frame
// line's rate and estimate of the time left, the stage line of a silent stage, and -q's silence.
// A large mesh's run printed only the elapsed time, and nothing through tens of seconds of
// preparation.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <mutex>
#include <regex>
#include <sstream>
#include <streambuf>
#include <string>
#include <thread>
#include <vector>

// The CLI's own headers (header-only), by their path from here: test_cli has no include path
// to the project root.
#include "../../cli/run_observers.hpp"
#include "../../cli/stage_notice.hpp"
#include "core/progress_stage.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/run.hpp"
#include "support/cli_runner.hpp"
#include "support/scratch_dir.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

using cli::ProgressPrinter;
using cli::StageNotice;
using Clock = std::chrono::steady_clock;

/// A stream another thread may write while this one reads (the notice's watcher).
class SharedText : public std::streambuf {
 public:
  std::string text() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return text_;
  }

 protected:
  int overflow(int c) override {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (c != traits_type::eof()) text_ += static_cast<char>(c);
    return c;
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    const std::lock_guard<std::mutex> lock(mutex_);
    text_.append(s, static_cast<std::size_t>(n));
    return n;
  }

 private:
  mutable std::mutex mutex_;
  std::string text_;
};

/// "9.24 s", "5 min 07 s", "2 h 05 min" as seconds (cli::duration_text).
double seconds_of(const std::string& text) {
  std::smatch m;
  if (std::regex_match(text, m, std::regex(R"(([0-9.e+-]+) s)"))) return std::stod(m[1]);
  if (std::regex_match(text, m, std::regex(R"((\d+) min (\d\d) s)")))
    return 60.0 * std::stod(m[1]) + std::stod(m[2]);
  if (std::regex_match(text, m, std::regex(R"((\d+) h (\d\d) min)")))
    return 3600.0 * std::stod(m[1]) + 60.0 * std::stod(m[2]);
  ADD_FAILURE() << "not a duration: '" << text << "'";
  return -1.0;
}

/// Every callback in order: "stage: WHAT", "started", "frame", "finished".
class Recorder final : public RunObserver {
 public:
  void stage(const std::string& what) override { calls.push_back("stage: " + what); }
  void started(const FrameView&) override { calls.push_back("started"); }
  void frame(const FrameView&, const FrameMetrics&) override { calls.push_back("frame"); }
  void finished(const FrameView&, const RunResult&) override { calls.push_back("finished"); }
  std::vector<std::string> calls;
};

std::ptrdiff_t index_of(const std::vector<std::string>& calls, const std::string& call) {
  const auto it = std::find(calls.begin(), calls.end(), call);
  return it == calls.end() ? -1 : it - calls.begin();
}

TEST(CliProgressStages, TheObserverHearsThePreparationsStagesInOrderThenTheEndsCheck) {
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/bumpy_sphere.off");
  RunOptions o;
  o.regions = RegionSource::Auto;
  o.sim.frames = 3;
  o.sim.validate = ValidateMode::End;
  Recorder rec;
  const RunResult r = run_contraction(mesh, o, &rec);
  ASSERT_EQ(r.frames_run, 3) << r.message;
  const std::vector<std::string>& c = rec.calls;
  std::string all;
  for (const std::string& s : c) all += s + "\n";
  // The preparation's stages, in the order they run, all before the first frame.
  const std::vector<std::string> expected = {"stage: selecting the regions",
                                             "stage: selecting the regions (curvature)",
                                             "stage: selecting the regions (shape)",
                                             "stage: choosing the contact distance",
                                             "stage: building the rest state",
                                             "stage: building the constraints",
                                             "stage: setting up the constraint solver (colouring)",
                                             "stage: finding the contact pairs at rest",
                                             "stage: counting the input's self-intersections",
                                             "started"};
  std::ptrdiff_t previous = -1;
  for (const std::string& e : expected) {
    const std::ptrdiff_t at = index_of(c, e);
    EXPECT_GT(at, previous) << e << " missing or out of order in:\n" << all;
    previous = std::max(previous, at);
  }
  // After started(): two frames, then the last step's check (`validate` end) before its
  // frame, then finished(). No stage between the other steps.
  const std::ptrdiff_t started = index_of(c, "started");
  ASSERT_GE(started, 0) << all;
  const std::vector<std::string> end(c.begin() + started, c.end());
  EXPECT_EQ(end, (std::vector<std::string>{"started", "frame", "frame",
                                           "stage: checking the result for self-intersections",
                                           "frame", "finished"}))
      << all;
}

TEST(CliProgressStages, AScopeHearsOnlyItsOwnThreadAndANestedScopeTakesOver) {
  std::vector<std::string> outer, inner;
  progress_stage("nobody");  // without a scope: nothing, no failure
  {
    const ProgressStageScope a([&](const std::string& s) { outer.push_back(s); });
    progress_stage("one");
    {
      const ProgressStageScope b([&](const std::string& s) { inner.push_back(s); });
      progress_stage("two");
      std::thread([] { progress_stage("another thread"); }).join();
    }
    progress_stage("three");
  }
  progress_stage("after");
  EXPECT_EQ(outer, (std::vector<std::string>{"one", "three"}));
  EXPECT_EQ(inner, (std::vector<std::string>{"two"}));
}

TEST(CliProgress, TheFrameLineGivesTheRateAndAnEstimateThatFallsToZeroAtConstantSpeed) {
  // A clock that moves `step` seconds at each reading: the printer reads it once as it is made,
  // once as the run starts and once per frame, so every frame takes `step` and gets a line.
  for (const double step : {1.5, 37.0}) {
    Clock::time_point t{};
    const auto tick = [&t, step] {
      t += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(step));
      return t;
    };
    SharedText buffer;
    std::ostream out(&buffer);
    StageNotice notice(out, false);
    const int frames = 12;
    ProgressPrinter progress(frames, "", notice, tick);
    RunOptions o;
    o.sim.frames = frames;
    const RunResult r =
        run_contraction(read_input_mesh(std::string(test::MESH_DIR) + "/ico2.off"), o, &progress);
    ASSERT_EQ(r.frames_run, frames) << r.message;
    const std::regex line(
        R"(frame (\d+)/12  V/V0 [0-9.]+  (.+)  ([0-9.e+-]+) s/frame  ~(.+) left \(estimate\))");
    std::istringstream lines(buffer.text());
    std::string text;
    int seen = 0;
    double previous_left = 1e300;
    while (std::getline(lines, text)) {
      std::smatch m;
      if (text.rfind("prepared in", 0) == 0) continue;
      ASSERT_TRUE(std::regex_match(text, m, line)) << "'" << text << "'";
      const int frame = std::stoi(m[1]);
      EXPECT_EQ(frame, seen + 1) << text;
      seen = frame;
      EXPECT_NEAR(seconds_of(m[2]), frame * step, 0.01 * frame * step) << text;  // elapsed
      EXPECT_NEAR(std::stod(m[3]), step, 1e-6 * step) << text;
      const double left = seconds_of(m[4]);
      EXPECT_NEAR(left, (frames - frame) * step, 0.01 * (frames - frame) * step + 0.5) << text;
      EXPECT_LT(left, previous_left) << text;
      previous_left = left;
    }
    EXPECT_EQ(seen, frames) << buffer.text();
    EXPECT_EQ(previous_left, 0.0) << buffer.text();
  }
}

TEST(CliProgress, AStageSilentLongerThanTheSilenceIsNamedOnceAndAShortOneNot) {
  SharedText buffer;
  std::ostream out(&buffer);
  {
    StageNotice notice(out, true, std::chrono::milliseconds(0));
    notice.begin("selecting the regions (curvature)");
    // The watcher names it (at once: no silence asked); waited for, not timed.
    const auto give_up = Clock::now() + std::chrono::seconds(60);
    while (buffer.text().empty() && Clock::now() < give_up)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    notice.line("a line of the command's");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    notice.end();
  }
  EXPECT_EQ(buffer.text(), "selecting the regions (curvature) ...\na line of the command's\n");

  SharedText quiet;
  std::ostream quiet_out(&quiet);
  {
    StageNotice notice(quiet_out, true, std::chrono::hours(1));
    notice.begin("reading big.off");
    notice.begin("checking big.off");
    notice.end();
  }
  EXPECT_EQ(quiet.text(), "");  // each stage ended within its silence: nothing said
  {
    StageNotice off(quiet_out, false, std::chrono::milliseconds(0));  // run -q
    off.begin("reading big.off");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_EQ(quiet.text(), "");
}

class CliProgressRun : public test::ScratchDirTest {
 protected:
  CliProgressRun() : ScratchDirTest("shellcontract_progress_") {}
};

TEST_F(CliProgressRun, ARunPrintsTheRateAndEstimateAtItsLastFrameAndNothingUnderQuiet) {
  const std::string in = std::string(test::MESH_DIR) + "/ico2.off";
  const std::string out = (dir_ / "out.off").string();
  const test::RunResult loud = test::run_cli({"run", in, "-o", out, "--frames", "5"});
  ASSERT_EQ(loud.exit_code, 0) << loud.output;
  EXPECT_TRUE(std::regex_search(
      loud.output,
      std::regex(R"(frame 5/5  V/V0 [0-9.]+  .+ s  [0-9.e+-]+ s/frame  ~0 s left \(estimate\)\n)")))
      << loud.output;
  // -q: no progress and no stage line (the notice has no thread): nothing, for this run.
  const test::RunResult quiet = test::run_cli({"run", in, "-o", out, "--frames", "5", "-q"});
  ASSERT_EQ(quiet.exit_code, 0) << quiet.output;
  EXPECT_EQ(quiet.output, "");
  // With every stage of the preparation and the end: warnings only.
  const test::RunResult stages = test::run_cli(
      {"run", in, "-o", out, "--frames", "5", "-q", "--regions", "auto", "--validate", "end"});
  std::istringstream lines(stages.output);
  for (std::string line; std::getline(lines, line);)
    EXPECT_EQ(line.rfind("warning: ", 0), 0u) << stages.output;
}

}  // namespace
}  // namespace shellcontract
