// An array of slots that a request fills in one by one and most requests never reach (the pair
// bounds the surface tree computes on first read): taken from calloc, whose large blocks are fresh
// zero pages the kernel maps only where written, so a slot costs resident memory once written and
// the array costs no zero-fill when made. Its size is still what a cache must reserve for it.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>

namespace tessera {

// T: an implicit-lifetime type (calloc's zero bytes are then a T) that needs no destructor.
template <typename T>
class ZeroedSlots {
  static_assert(std::is_trivially_destructible_v<T> && std::is_trivially_copyable_v<T>);

 public:
  ZeroedSlots() = default;
  explicit ZeroedSlots(size_t count) : data_(static_cast<T*>(std::calloc(count, sizeof(T)))) {
    if (count > 0 && data_ == nullptr) throw std::bad_alloc();
  }

  // Writable through a const array, as a unique_ptr's elements are: the slots are the array's
  // mutable cache, and their writers synchronise themselves.
  T& operator[](size_t i) const { return data_.get()[i]; }

 private:
  struct Free {
    void operator()(T* p) const { std::free(p); }
  };
  std::unique_ptr<T, Free> data_;
};

}  // namespace tessera
