// Memory running out where the library can say what needed it.
#pragma once

#include <new>
#include <stdexcept>
#include <string>

namespace shellcontract {

/// An input (a mesh, a point set, a checkpoint) larger than the memory there is to read it. A
/// std::bad_alloc, so that whatever handles memory running out handles it too: exit code 3
/// (README "Exit codes"; memory is short, not the file unusable) and Python's MemoryError, with
/// the message a front end prints ("<file>: out of memory: reading it needs more memory ...").
class OutOfMemoryError : public std::bad_alloc {
 public:
  explicit OutOfMemoryError(const std::string& message) : message_(message) {}
  const char* what() const noexcept override { return message_.what(); }

 private:
  std::runtime_error message_;  ///< the text, copied without allocating (as an exception must be)
};

}  // namespace shellcontract
