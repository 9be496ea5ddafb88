// An array of slots that a request fills in one by one and most requests never reach (the pair
// bounds the surface tree computes on first read): large arrays are mapped anonymously, fresh zero
// pages the kernel backs only where written, so a slot costs resident memory once written and the
// array costs no zero-fill when made (calloc would reuse, and clear, freed heap memory once malloc's
// mmap threshold has grown past the array). Its size is still what a cache must reserve for it.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <new>
#include <type_traits>
#include <utility>

namespace tessera {

// T: an implicit-lifetime type (zero bytes are then a T) that needs no destructor.
template <typename T>
class ZeroedSlots {
  static_assert(std::is_trivially_destructible_v<T> && std::is_trivially_copyable_v<T>);

 public:
  ZeroedSlots() = default;
  explicit ZeroedSlots(size_t count) : bytes_(count * sizeof(T)) {
    if (bytes_ >= kMapped) {
      void* at = mmap(nullptr, bytes_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
      if (at == MAP_FAILED) throw std::bad_alloc();
      data_ = static_cast<T*>(at);
    } else if (count > 0) {
      data_ = static_cast<T*>(std::calloc(count, sizeof(T)));
      if (data_ == nullptr) throw std::bad_alloc();
    }
  }
  ZeroedSlots(ZeroedSlots&& other) noexcept
      : data_(std::exchange(other.data_, nullptr)), bytes_(std::exchange(other.bytes_, 0)) {}
  ZeroedSlots& operator=(ZeroedSlots&& other) noexcept {
    std::swap(data_, other.data_);
    std::swap(bytes_, other.bytes_);
    return *this;
  }
  ZeroedSlots(const ZeroedSlots&) = delete;
  ZeroedSlots& operator=(const ZeroedSlots&) = delete;
  ~ZeroedSlots() {
    if (data_ == nullptr) return;
    if (bytes_ >= kMapped) {
      munmap(data_, bytes_);
    } else {
      std::free(data_);
    }
  }

  // Writable through a const array, as a unique_ptr's elements are: the slots are the array's
  // mutable cache, and their writers synchronise themselves.
  T& operator[](size_t i) const { return data_[i]; }

 private:
  static constexpr size_t kMapped = size_t(1) << 20;  // smaller arrays: calloc
  T* data_ = nullptr;
  size_t bytes_ = 0;
};

}  // namespace tessera
