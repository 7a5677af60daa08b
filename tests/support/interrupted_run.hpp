// What the interrupt tests look for around a run they stop (docs/design/output-safety.md): when
// it is in its frames, and which temporaries it left.
#pragma once

#include <chrono>
#include <filesystem>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

namespace shellcontract::test {

/// Waits (at most 60 s) until `dir` holds a file: the run is past its preparation, in its frames.
inline bool await_file_in(const std::filesystem::path& dir) {
  for (int i = 0; i < 6000; ++i) {
    std::error_code ec;
    if (std::filesystem::exists(dir, ec) && !std::filesystem::is_empty(dir, ec)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

/// The temporaries under `dir` (the writers' "*.tmp.*" files and the output checks' probes,
/// ".shellcontract-probe" cut to the length of the name they stand for).
inline std::vector<std::string> temporaries(const std::filesystem::path& dir) {
  std::vector<std::string> found;
  std::error_code ec;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir, ec))
    if (e.path().filename().string().find(".tmp.") != std::string::npos ||
        e.path().filename().string().rfind(".shell", 0) == 0)
      found.push_back(e.path().string());
  return found;
}

}  // namespace shellcontract::test
