// The check that a PLY document's float32 x, y, z can hold the positions (ply_slots.hpp).
#include "mesh/ply_slots.hpp"

#include <charconv>
#include <cmath>
#include <limits>

#include "shellcontract/error.hpp"

namespace shellcontract::ply {

void require_representable(const std::string& name, const std::vector<Slot>& slots,
                           const Positions& x) {
  const auto refuse = [&](std::size_t k, const std::string& why) {
    char v[64];  // the shortest text that reads back as the value
    const auto end = std::to_chars(
        v, v + sizeof v, x(static_cast<Eigen::Index>(k / 3), static_cast<Eigen::Index>(k % 3)));
    throw UsageError("the positions do not fit " + name + "'s vertex types: vertex " +
                     std::to_string(k / 3) + "'s " + "xyz"[k % 3] + " is " +
                     std::string(v, end.ptr) + ", " + why);
  };
  double largest = 0.0;
  std::size_t at = 0;
  for (std::size_t k = 0; k < slots.size(); ++k) {
    const double v = x(static_cast<Eigen::Index>(k / 3), static_cast<Eigen::Index>(k % 3));
    if (written_type(slots[k]) == Type::Float32) {
      if (std::isinf(static_cast<float>(v)))
        refuse(k, "beyond the largest 32-bit float (3.40282347e+38) that the file stores it as");
      if (std::abs(v) > largest) largest = std::abs(v), at = k;
    }
  }
  if (largest > 0.0 && largest < static_cast<double>(std::numeric_limits<float>::min()))
    refuse(at,
           "the largest float32 coordinate, below the smallest normal 32-bit float "
           "(1.17549435e-38): stored as the file's floats, the positions would be zero or keep a "
           "few bits");
}

}  // namespace shellcontract::ply
