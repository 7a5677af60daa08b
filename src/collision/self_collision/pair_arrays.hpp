// Storage for the per-pair arrays of the collision step (its records and flags, the live list
// and the tests), which every broad phase rewrites whole, in parallel, right after sizing them.
#pragma once

#include "shellcontract/core/no_zero_allocator.hpp"

namespace shellcontract {

/// A per-pair array: sized with resize_for_rewrite (shellcontract/core/no_zero_allocator.hpp),
/// then written whole.
template <class T>
using PairArray = NoZeroVector<T>;

}  // namespace shellcontract
