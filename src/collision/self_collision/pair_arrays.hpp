// Storage for the per-pair arrays of the collision step (its records and flags, the live list
// and the tests), which every broad phase rewrites whole, in parallel, right after sizing them.
#pragma once

#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace shellcontract {

/// std::allocator, except that an element made without a value is default-initialized: a
/// trivially constructible element is left as it is, so resize() does not zero the growth on
/// one thread before the parallel fill writes it anyway.
template <class T>
struct NoZeroAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = NoZeroAllocator<U>;
  };
  NoZeroAllocator() = default;
  template <class U>
  NoZeroAllocator(const NoZeroAllocator<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <class T>
using PairArray = std::vector<T, NoZeroAllocator<T>>;

/// Sizes v to n for contents the caller then writes whole: growth past the capacity takes fresh
/// storage (twice n) instead of copying elements that are about to be overwritten.
/// The stage timers of bear x16 (docs/benchmarks/scale.md, "Sixteen cores") had the growth of
/// these arrays serial, 8.5-10 ms per step at any thread count over the first ten frames.
/// Twice, not a quarter more: the pairs grow as the shell contracts, and glibc serves blocks
/// this large with a fresh mapping, whose every page faults on first write; with a quarter, the
/// arrays were taken anew every few frames and bear x16's pair records cost about twice as much
/// (docs/benchmarks/scale.md, "Page faults"). The reserve beyond what is written is never
/// touched, so it is not resident.
template <class T>
void resize_for_rewrite(PairArray<T>& v, std::size_t n) {
  if (n > v.capacity()) {
    PairArray<T> fresh;
    fresh.reserve(2 * n);
    v.swap(fresh);
  }
  v.resize(n);
}

}  // namespace shellcontract
