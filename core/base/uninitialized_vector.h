// A std::vector whose resize leaves new elements of trivial types uninitialized, for large
// per-request outputs that are written in full right after (on all cores): resizing a plain vector
// zero-fills it on one thread first, which on the largest requests costs more than the writes.
#pragma once

#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace tessera {

template <typename T>
struct DefaultInitAllocator : std::allocator<T> {
  template <typename U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  using std::allocator<T>::allocator;

  // Default-initialises (no value for trivial types) instead of value-initialising.
  template <typename U>
  void construct(U* at) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(at)) U;
  }
  template <typename U, typename... Args>
  void construct(U* at, Args&&... args) {
    std::allocator_traits<std::allocator<T>>::construct(static_cast<std::allocator<T>&>(*this), at,
                                                        std::forward<Args>(args)...);
  }
};

template <typename T>
using UninitializedVector = std::vector<T, DefaultInitAllocator<T>>;

}  // namespace tessera
