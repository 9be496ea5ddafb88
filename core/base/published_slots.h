// Values computed on first read and kept, one slot per index, shared by concurrent readers: the
// first to finish computing publishes its value, the others use their own (the same, when the
// computation is deterministic). Slots cost resident memory only once written (ZeroedSlots).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>

#include "core/base/zeroed_slots.h"

namespace tessera {

template <typename T>
class PublishedSlots {
 public:
  PublishedSlots() = default;
  explicit PublishedSlots(size_t count) : states_(count), values_(count) {}

  bool known(size_t i) const { return std::atomic_ref(states_[i]).load(std::memory_order_acquire) == kDone; }
  // Only once known(i).
  const T& operator[](size_t i) const { return values_[i]; }
  // Keeps `value` as slot i's unless another thread published first.
  void publish(size_t i, const T& value) const {
    const std::atomic_ref state(states_[i]);
    uint8_t expected = kEmpty;
    if (!state.compare_exchange_strong(expected, kWriting, std::memory_order_acquire)) return;
    values_[i] = value;
    state.store(kDone, std::memory_order_release);
  }
  static constexpr size_t kBytesPerSlot = sizeof(uint8_t) + sizeof(T);

 private:
  static constexpr uint8_t kEmpty = 0, kWriting = 1, kDone = 2;
  ZeroedSlots<uint8_t> states_;
  ZeroedSlots<T> values_;
};

}  // namespace tessera
