#include "shellcontract/version.hpp"

#include <cstdlib>
#include <cstring>
#include <string>

#include "build_source.hpp"  // generated: SHELLCONTRACT_BUILD_SOURCE (cmake/BuildIdentity.cmake)
#include "core/kernels.hpp"
#include "pbd/constraint_batches.hpp"
#include "shellcontract/error.hpp"

#ifndef SHELLCONTRACT_RELEASE
#define SHELLCONTRACT_RELEASE "unknown"
#endif

namespace shellcontract {

const char* release_version() { return SHELLCONTRACT_RELEASE; }

const char* build_version() {
  static const std::string build =
      std::strlen(SHELLCONTRACT_BUILD_SOURCE) == 0
          ? std::string(SHELLCONTRACT_RELEASE)
          : std::string(SHELLCONTRACT_RELEASE "+" SHELLCONTRACT_BUILD_SOURCE);
  return build.c_str();
}

const char* kernel_class() {
  const char* v = std::getenv("SHELLCONTRACT_KERNELS");
  if (v != nullptr && *v != '\0' && std::strcmp(v, "auto") != 0 && std::strcmp(v, "scalar") != 0)
    throw UsageError(std::string("SHELLCONTRACT_KERNELS: expected 'auto' or 'scalar', got '") + v +
                     "'");
  return detail::kernels_in_use();
}

namespace detail {

const char* kernels_in_use() {
  // batch_avx2_available() already asks vector_kernels_allowed(): the kernels that decide the
  // result's bits are the constraint kernels; the broad phase's and the CCD filter's vector
  // paths give their scalar paths' answers.
  return batch_avx2_available() ? "avx2" : "scalar";
}

}  // namespace detail

std::string tool_identity() {
  return std::string(build_version()) + " (" + kernel_class() + " kernels)";
}

}  // namespace shellcontract
