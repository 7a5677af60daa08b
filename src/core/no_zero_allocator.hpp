// An allocator for arrays that are sized first and then written whole, in parallel.
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

/// A std::vector whose resize() leaves new trivially constructible elements unwritten.
template <class T>
using NoZeroVector = std::vector<T, NoZeroAllocator<T>>;

/// Sizes v to n for contents the caller then writes whole: growth past the capacity takes fresh
/// storage (twice n) instead of copying elements that are about to be overwritten, and the new
/// elements are left unwritten. Used for the collision step's per-pair arrays and the broad
/// phase's candidate lists, which grow as the shell contracts. Twice, not a quarter more: glibc
/// serves blocks this large with a fresh mapping, whose every page faults on its first write, and
/// with a quarter the largest meshes' pair arrays were taken anew every few frames, which added
/// much to the cost of their pair records (lab/pages/scale.md, "Page faults of the pair
/// arrays"). The reserve
/// beyond what is written is never touched, so it is not resident.
template <class T>
void resize_for_rewrite(NoZeroVector<T>& v, std::size_t n) {
  if (n > v.capacity()) {
    NoZeroVector<T> fresh;
    fresh.reserve(2 * n);
    v.swap(fresh);
  }
  v.resize(n);
}

}  // namespace shellcontract
