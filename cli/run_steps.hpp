// The steps of `shellcontract run`, which command_run (run.cpp) takes in this order: the command
// line read, checked and its files claimed (prepare_run, run_prepare.cpp); the input read and the
// observers made (run_input.cpp); the run; its files written and its end reported
// (run_outputs.cpp). Each step is one job; what they share travels in RunRequest.
#pragma once

#include <boost/program_options.hpp>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "export_observer.hpp"
#include "json_writer.hpp"
#include "output_paths.hpp"
#include "run_checkpoint.hpp"
#include "run_observers.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/observer.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/repair.hpp"
#include "shellcontract/report.hpp"
#include "shellcontract/run.hpp"
#include "sim/checkpoint.hpp"
#include "stage_notice.hpp"

namespace shellcontract::cli {

/// What the command line asks for: the values as given (boost writes them, describe_run_options),
/// then what prepare_run reads from them.
struct RunRequest {
  // As given.
  std::string input, output, log_path, summary_path, fields_prefix, fields_colour = "mean";
  std::string export_failure = "warn", gltf_fps;
  std::string checkpoint_path, resume_path;
  std::string checkpoint_every_text, export_every_text;  // frame_count reads them
  bool quiet = false, repair = false;
  std::map<std::string, std::string> values;  // the option table's (add_table_options)
  std::map<std::string, bool> switches;
  std::map<std::string, std::vector<std::string>> lists;
  ExportRequest exports;  // dir and gltf as given; the rest from the other options

  // Read from them.
  RunOptions options;
  FieldColour colour = FieldColour::MeanCurvature;
  int checkpoint_every = 0;
  bool saves_to_resumed = false;  // run --resume FILE without --checkpoint: saves to FILE
  Checkpoint resume;
  std::vector<RunInput> inputs;  // the face list or weights file, recorded in checkpoints
};

/// What a run holds from its preparation until it ends.
struct RunClaims {
  std::unique_ptr<ExportFolderLock> export_lock;  // held until the run's files are written
  PlannedFrames frames;                           // of --export-dir, for what a failed run leaves
  CheckpointLocks checkpoint_locks;
  CheckpointLocks resumed;  // --resume's, taken before it is read: into checkpoint_locks
};

/// For a message if memory runs out outside the frames (those end the run with the last good
/// state, see run_contraction): what the tool was doing, and what it had written.
struct RunTrace {
  std::string stage;
  std::string faces;    // "N faces" once the mesh is read
  std::string written;  // "A and B"
};

/// Boost's description of run's options, bound to `request` (run --help prints it).
void describe_run_options(boost::program_options::options_description& desc, RunRequest& request);

/// Parses and checks the command line and claims the run's files (one decision for every output,
/// output_paths.hpp; the export folder; the checkpoints' locks). Nothing before the claim creates
/// a file or folder.
/// @return the exit code when the command ends here (--help, bad usage, a bad checkpoint), else
///         nullopt: the run goes on with `request` and `claims`
std::optional<int> prepare_run(int argc, char** argv,
                               const boost::program_options::options_description& desc,
                               RunRequest& request, RunClaims& claims);

/// The input mesh as read (and repaired with --repair), with what the reader said.
struct RunInputMesh {
  Mesh mesh;
  InputReport report;
  RepairReport repair_report;
  double read_seconds = 0.0;  // reading, checking and repairing
};

/// Reads the input (repairs it with --repair), prints the reader's warnings and notes, refuses a
/// mesh that an STL result cannot hold, and says how long a slow read took.
/// @throws UsageError, InputError as the reader and the checks do
RunInputMesh read_run_input(const RunRequest& request, StageNotice& notice);

/// The CLI's observers of one run, in the order the run tells them, and its checkpointer.
/// Declared in the order they are made and (backwards) destroyed.
class RunObservers {
 public:
  /// Checks a resumed run's input against its checkpoint (InputError: exit 2), makes the
  /// observers the request asks for, and refuses outputs too large for their format.
  RunObservers(const RunRequest& request, const Mesh& mesh,
               const std::shared_ptr<const MeshDocument>& document, StageNotice& notice);

  ObserverList list;
  WarningPrinter warnings;
  ProgressPrinter progress;
  CsvLog csv;
  std::optional<CliCheckpointer> checkpointer;  // made once the CSV log has its resumed lines
  FieldsWriter fields;
  FrameExporter exporter;
};

/// Writes the run's files one at a time: one that fails (a full disk) is reported and the others
/// are still written (output-safety.md).
class OutputWriter {
 public:
  OutputWriter(StageNotice& notice, RunTrace& trace) : notice_(notice), trace_(trace) {}
  /// Writes one output with `write`, recording "written" or why it failed (a file there before
  /// the run is left as it was).
  void attempt(const char* option, const std::string& path, const std::function<void()>& write);
  /// Every file written from the document (frames, result) warns alike of the input: once a run.
  void warn_once(const std::string& warning);
  /// What warn_once said, in order (the summary's `warnings` end with them).
  const std::vector<std::string>& warnings() const { return said_; }

  OutputStatus outputs;

 private:
  StageNotice& notice_;
  RunTrace& trace_;
  std::set<std::string> warned_;
  std::vector<std::string> said_;
};

/// Writes every output of a finished run (the summary last, naming how the others went).
void write_run_outputs(OutputWriter& writer, const RunRequest& request, const RunInputMesh& input,
                       const std::shared_ptr<const MeshDocument>& document, const RunResult& r,
                       RunObservers& observers);

/// Says how the run ended (stderr) and returns the process's exit code.
int report_run_end(const RunRequest& request, const RunResult& r, const OutputStatus& outputs);

}  // namespace shellcontract::cli
