#include "export/frame_sequence_writer.hpp"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <stdexcept>

#include "mesh/formats.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

int decimal_digits(int n) {
  int digits = 1;
  for (; n >= 10; n /= 10) ++digits;
  return digits;
}

}  // namespace

std::string frame_file_name(const std::string& dir, const std::string& name, const std::string& ext,
                            int frame, int max_frame) {
  if (frame < 0 || frame > max_frame)
    throw std::invalid_argument("frame_file_name: frame " + std::to_string(frame) +
                                " outside [0, " + std::to_string(max_frame) + "]");
  std::string number = std::to_string(frame);
  number.insert(0, static_cast<std::size_t>(decimal_digits(max_frame)) - number.size(), '0');
  const std::string file = name + "_" + number + "." + ext;
  return dir.empty() ? file : (std::filesystem::path(dir) / file).string();
}

FrameSequenceWriter::FrameSequenceWriter(std::string dir, std::string name, std::string ext,
                                         const Mesh& mesh, int max_frame,
                                         std::size_t queue_capacity,
                                         std::shared_ptr<const MeshDocument> document)
    : dir_(std::move(dir)),
      name_(std::move(name)),
      ext_(std::move(ext)),
      mesh_(mesh),
      document_(std::move(document)),
      max_frame_(max_frame),
      capacity_(std::max<std::size_t>(queue_capacity, 1)) {
  std::transform(ext_.begin(), ext_.end(), ext_.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (!ext_.empty() && ext_.front() == '.') ext_.erase(0, 1);
  if (!is_mesh_format(ext_, &MeshFormat::plain_writer))
    throw UsageError("frame sequence: unknown format '" + ext_ + "' (expected " +
                     extension_list(&MeshFormat::plain_writer, "") + ")");
  if (max_frame_ < 0) throw std::invalid_argument("FrameSequenceWriter: max_frame < 0");
  if (mesh_.has_garbage())
    throw std::invalid_argument(
        "FrameSequenceWriter: the mesh has removed elements; call collect_garbage() first");
  if (document_ && (document_->format() != ext_ || !document_->matches(mesh_)))
    throw std::invalid_argument("FrameSequenceWriter: the document is not one of this mesh in ." + ext_);
  thread_ = std::thread([this] { work(); });
}

FrameSequenceWriter::~FrameSequenceWriter() {
  try {
    finish();
  } catch (...) {
    // Not collected by finish(): dropped (a destructor must not throw).
  }
}

std::string FrameSequenceWriter::file_name(int frame) const {
  return frame_file_name(dir_, name_, ext_, frame, max_frame_);
}

void FrameSequenceWriter::write(int frame, const Positions& x_input_units) {
  const auto start = Clock::now();
  if (static_cast<std::size_t>(x_input_units.rows()) != mesh_.number_of_vertices())
    throw std::invalid_argument(
        "FrameSequenceWriter::write: " + std::to_string(x_input_units.rows()) +
        " position rows for " + std::to_string(mesh_.number_of_vertices()) + " vertices");
  if (frame < 0 || frame > max_frame_)
    throw std::invalid_argument("FrameSequenceWriter::write: frame " + std::to_string(frame) +
                                " outside [0, " + std::to_string(max_frame_) + "]");
  Positions copy = x_input_units;  // outside the lock: the writer keeps going meanwhile
  std::unique_lock<std::mutex> lock(mutex_);
  if (stopping_) throw std::invalid_argument("FrameSequenceWriter::write after finish()");
  queue_changed_.wait(lock, [this] { return queue_.size() < capacity_ || error_; });
  if (!error_) {
    queue_.emplace_back(frame, std::move(copy));
    queue_changed_.notify_all();
  }
  stats_.caller_seconds += seconds_since(start);
}

void FrameSequenceWriter::work() {
  // The lowest priority for this thread alone (Linux applies nice per thread): the simulation's
  // threads, the speculative broad phase on the spare core among them, come first and the files
  // are written in their idle time.
  setpriority(PRIO_PROCESS, static_cast<id_t>(::syscall(SYS_gettid)), 19);
  for (;;) {
    std::pair<int, Positions> item;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      queue_changed_.wait(lock, [this] { return !queue_.empty() || stopping_; });
      if (queue_.empty()) return;  // stopping and nothing left
      item = std::move(queue_.front());
      // The frame stays counted against the capacity until it is written: bounded memory.
    }
    const auto start = Clock::now();
    std::uint64_t bytes = 0;
    std::exception_ptr error;
    std::vector<std::string> warnings;
    try {
      const std::string path = file_name(item.first);
      // As the run's -o output is written (cli/run.cpp), so that a frame and the result of a run
      // that ends there are the same file.
      if (document_)
        write_mesh_document_atomic(path, *document_, input_positions(mesh_, item.second), &warnings);
      else
        write_mesh_atomic(path, mesh_, item.second);
      bytes = std::filesystem::file_size(path);
    } catch (...) {
      error = std::current_exception();
    }
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.pop_front();
    stats_.writer_seconds += seconds_since(start);
    if (error) {
      if (!error_) error_ = error;
      queue_.clear();  // later frames are dropped after an error
    } else {
      ++stats_.frames_written;
      stats_.bytes += bytes;
      if (document_ && !warned_) {
        warnings_ = std::move(warnings);
        warned_ = true;
      }
    }
    queue_changed_.notify_all();
  }
}

void FrameSequenceWriter::finish() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_) return;
    stopping_ = true;
    finished_ = true;
    queue_changed_.notify_all();
  }
  if (thread_.joinable()) thread_.join();
  std::exception_ptr error;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    error = error_;
  }
  if (error) std::rethrow_exception(error);
}

bool FrameSequenceWriter::failed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return error_ != nullptr;
}

std::vector<std::string> FrameSequenceWriter::warnings() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return warnings_;
}

ExportStats FrameSequenceWriter::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

}  // namespace shellcontract
