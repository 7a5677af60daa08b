// Frame sequence export: every exported frame of a run as its own mesh file, written on
// a background thread so that the writing overlaps the next simulation steps.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "shellcontract/mesh.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract {

class MeshDocument;

/// What exporting cost; the CLI puts it in the run's summary.
struct ExportStats {
  int frames_written = 0;       ///< files completely written (renamed into place)
  std::uint64_t bytes = 0;      ///< total size of those files
  double caller_seconds = 0.0;  ///< time spent in write() by the calling (simulation) thread:
                                ///< copying the positions, enqueueing, waiting for queue room
  double writer_seconds = 0.0;  ///< time the background thread spent formatting and writing
};

/// File name of one frame: `dir/<name>_<frame>.<ext>`, the frame number zero-padded to the
/// number of digits of `max_frame` (so that the names sort in frame order).
/// @param max_frame largest frame number that will be written (>= frame, >= 0)
std::string frame_file_name(const std::string& dir, const std::string& name, const std::string& ext,
                            int frame, int max_frame);

/// Writes frames of a run as separate mesh files, one background thread, a bounded queue of
/// copied positions. Each file is written as the run's -o output is: through the input's document
/// when one is given (an OBJ or PLY input written in its own format: UVs, normals, groups,
/// materials, polygons and extra properties kept; docs/design/attributes.md), else with
/// write_mesh_atomic (OFF, OBJ, PLY or STL, full precision); a mesh welded along its seams gets
/// its input's vertices back either way. Both write atomically (write_file_atomic: an exclusive
/// temporary, renamed). It only reads the positions it is given, so exporting cannot change a
/// simulation; the file contents depend only on the positions, the connectivity and the document
/// (not on timing).
///
/// Errors (unwritable folder, disk full) happen on the writer thread: the frames after the first
/// error are dropped and finish() rethrows that error. write() throws only for bad arguments.
class FrameSequenceWriter {
 public:
  /// Frames waiting to be written at most; write() blocks while the queue is full.
  static constexpr std::size_t DEFAULT_QUEUE_CAPACITY = 4;

  /// @param dir folder of the files (must exist; not created here)
  /// @param name file-name stem, e.g. the input's stem
  /// @param ext "off", "obj", "ply" or "stl" (without the dot, any case)
  /// @param mesh connectivity (copied: the caller may change or destroy it afterwards)
  /// @param max_frame largest frame number that will be written; sets the zero-padding width
  /// @param document  the input's document (shared: it is the whole input file), for the files
  ///                  when its format is `ext`; it must stand for `mesh` (MeshDocument::matches).
  ///                  nullptr: write_mesh_atomic
  /// @pre mesh is a triangle mesh without garbage
  /// @throws UsageError for an unknown extension
  /// @throws std::invalid_argument for a document of another format or another mesh
  FrameSequenceWriter(std::string dir, std::string name, std::string ext, const Mesh& mesh,
                      int max_frame, std::size_t queue_capacity = DEFAULT_QUEUE_CAPACITY,
                      std::shared_ptr<const MeshDocument> document = nullptr);
  /// Joins the thread; an error not collected by finish() is dropped.
  ~FrameSequenceWriter();
  FrameSequenceWriter(const FrameSequenceWriter&) = delete;
  FrameSequenceWriter& operator=(const FrameSequenceWriter&) = delete;

  /// Copies x (#V by 3, input units) and queues frame `frame` for writing.
  /// @throws std::invalid_argument if x has the wrong number of rows, frame is outside
  ///         [0, max_frame], or finish() was already called
  void write(int frame, const Positions& x_input_units);

  /// Waits until every queued frame is written, stops the thread and rethrows the first error
  /// of the writer thread, if any. Calling it again does nothing.
  void finish();

  /// The file name that write(frame, ...) produces.
  std::string file_name(int frame) const;

  /// Counters so far (safe to call at any time).
  ExportStats stats() const;

  /// Whether a frame failed to be written (safe to call at any time); finish() rethrows it.
  bool failed() const;

  /// What writing the first frame file through the document warned about (a material library
  /// of the OBJ that does not exist: write_mesh_document_atomic); the later frames are in the
  /// same folder and would say the same. Safe to call at any time.
  std::vector<std::string> warnings() const;

 private:
  void work();

  std::string dir_, name_, ext_;
  Mesh mesh_;
  std::shared_ptr<const MeshDocument> document_;
  int max_frame_;
  std::size_t capacity_;

  mutable std::mutex mutex_;
  std::condition_variable queue_changed_;
  std::deque<std::pair<int, Positions>> queue_;
  bool stopping_ = false;
  bool finished_ = false;
  std::exception_ptr error_;
  ExportStats stats_;
  std::vector<std::string> warnings_;
  bool warned_ = false;  ///< warnings_ holds the first document frame's
  std::thread thread_;
};

}  // namespace shellcontract
