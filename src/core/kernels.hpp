// Whether the vector (SIMD) kernels may run: the CPU has them and SHELLCONTRACT_KERNELS does not
// say "scalar" (shellcontract/version.hpp, kernel_class). Every run-time dispatch to an AVX2 or
// AVX-512 path asks this first, so that "scalar" means no vector kernel at all.
#pragma once

namespace shellcontract::detail {

/// False when SHELLCONTRACT_KERNELS is "scalar"; true when it is unset, empty or "auto". Any
/// other value counts as "auto" here (a kernel has no way to report it); kernel_class(), which
/// the CLI and the Python module ask first, refuses it.
bool vector_kernels_allowed();

/// kernel_class() without the check of the variable: "avx2" or "scalar", what runs here
/// (src/core/version.cpp). For what is written after a run, which must not fail on it.
const char* kernels_in_use();

}  // namespace shellcontract::detail
