#include "core/kernels.hpp"

#include <cstdlib>
#include <cstring>

namespace shellcontract::detail {

bool vector_kernels_allowed() {
  // Read once: a kernel must not change mid-run (the runs' bits would be neither class's).
  static const bool allowed = [] {
    const char* v = std::getenv("SHELLCONTRACT_KERNELS");
    return v == nullptr || std::strcmp(v, "scalar") != 0;
  }();
  return allowed;
}

}  // namespace shellcontract::detail
