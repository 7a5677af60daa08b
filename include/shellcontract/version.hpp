// Which ShellContract this is: the release, the build (the source it was compiled from) and the
// kernels it runs on this machine. Results are the same bytes for the same build, kernels, input
// and options, whatever the thread count; another build or other kernels may differ in the last
// bits, which a long or contact-rich run amplifies. So a checkpoint names both and is refused by
// another (checkpoint.hpp), `shellcontract --version` prints both, and a sweep's job ids and its
// check of a cluster's workers take that text (docs/design/sweeps.md).
#pragma once

#include <string>

namespace shellcontract {

/// The release, "MAJOR.MINOR.PATCH": the CMake package's version.
const char* release_version();

/// The build: the release, then the commit it was built from and a hash of the uncommitted
/// changes to tracked files, as a PEP 440 local version: "0.2.0+g0123456789ab" or
/// "0.2.0+g0123456789ab.dirty.1a2b3c4d"; the release alone when built outside a git checkout.
/// A -march=native build (SHELLCONTRACT_NATIVE) adds its target, "native." and a hash of the
/// instruction set picked for its machine: "0.2.0+g0123456789ab.native.1a2b3c4d" ("0.2.0+native.
/// 1a2b3c4d" outside git), since it may round differently. Python's `shellcontract.__version__`.
const char* build_version();

/// The constraint kernels this process runs: "avx2" (the batched AVX2 + FMA kernels, on every
/// CPU that has them, AVX-512 ones too: the same bits) or "scalar" (a CPU without them, or the
/// environment variable SHELLCONTRACT_KERNELS=scalar, which a cluster of mixed CPUs can set on
/// every node to get one result everywhere, at a cost in speed). They round differently.
/// @throws UsageError when SHELLCONTRACT_KERNELS is set to other than "auto", "scalar" or empty
const char* kernel_class();

/// What `--version` prints after "shellcontract ", what a checkpoint and a sweep's job ids name:
/// build_version() and kernel_class(), "0.2.0+g0123456789ab (avx2 kernels)".
/// @throws UsageError as kernel_class()
std::string tool_identity();

}  // namespace shellcontract
