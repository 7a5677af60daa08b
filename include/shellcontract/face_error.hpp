// An InputError about particular faces, with their numbers as data: a front end that gave the
// library a triangulation of its own polygons (the Blender add-on) maps them back without reading
// the message's text.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "shellcontract/error.hpp"

namespace shellcontract {

/// The input mesh cannot be used because of some of its faces (exit code 2, as any InputError).
/// what() is the message as an InputError would read; faces() are the triangle indices it is
/// about (0-based, in the triangulated soup the checks ran on, the order the message names them;
/// for a non-manifold vertex, the faces around it in index order),
/// all of them: a message that shortens its list with "..." still has the whole list here. A
/// file's polygon refused before triangulation is given by its index, which is also the index of
/// its first triangle (the others are appended after the last polygon).
class FaceListError : public InputError {
 public:
  FaceListError(const std::string& message, std::vector<std::size_t> faces)
      : InputError(message), faces_(std::move(faces)) {}

  const std::vector<std::size_t>& faces() const { return faces_; }

 private:
  std::vector<std::size_t> faces_;
};

/// Throws `e` as its own type: a FaceListError keeps its faces (a plain `throw e` of an
/// InputError reference would slice them off).
[[noreturn]] inline void rethrow_input_error(const InputError& e) {
  if (const auto* f = dynamic_cast<const FaceListError*>(&e)) throw *f;
  throw e;
}

}  // namespace shellcontract
