// A 64-byte aligned array on transparent huge pages where the kernel grants them, written once
// when made so that no first-touch page fault lands in a timed region: what the FAS and
// tessellation benchmarks write into (and read their packed inputs from).
#pragma once

#include <cstddef>
#include <type_traits>

namespace tessera::bench {

// The raw allocation behind TouchedBuffer: whole 2 MiB pages, zeroed; freeTouched releases it.
void* allocateTouched(size_t bytes);
void freeTouched(void* data);

template <class T>
class TouchedBuffer {
  static_assert(std::is_trivially_copyable_v<T>);

 public:
  explicit TouchedBuffer(size_t count) : data_(static_cast<T*>(allocateTouched(count * sizeof(T)))), count_(count) {}
  ~TouchedBuffer() { freeTouched(data_); }
  TouchedBuffer(const TouchedBuffer&) = delete;
  TouchedBuffer& operator=(const TouchedBuffer&) = delete;

  T* data() { return data_; }
  const T* data() const { return data_; }
  size_t size() const { return count_; }
  size_t bytes() const { return count_ * sizeof(T); }

 private:
  T* data_ = nullptr;
  size_t count_ = 0;
};

}  // namespace tessera::bench
