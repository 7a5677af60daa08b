// The errors of the line-by-line scans (off_scan.cpp, obj_scan.cpp), one pair for both: a problem
// with the file's name, and a problem of one face with its index, so that the two readers word
// and type their refusals alike (private to src/mesh).
#pragma once

#include <cstddef>
#include <string>

#include "shellcontract/error.hpp"
#include "shellcontract/face_error.hpp"

namespace shellcontract::scan_errors {

/// An InputError "<path>: <problem>: <details>".
[[noreturn]] inline void fail(const std::string& path, const std::string& problem,
                              const std::string& details) {
  throw InputError(path + ": " + problem + ": " + details);
}

/// A problem of one face: a FaceListError with its index (a polygon's is its first triangle's,
/// face_error.hpp), so that a caller gets the face as data from a file as from arrays (the PLY
/// reader and the arrays' checks name theirs so too).
[[noreturn]] inline void fail_face(const std::string& path, const std::string& problem,
                                   const std::string& details, std::size_t face) {
  throw FaceListError(path + ": " + problem + ": " + details, {face});
}

}  // namespace shellcontract::scan_errors
