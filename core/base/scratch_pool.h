// Scratch room kept from call to call. A call takes one object for each thread that works for it
// and gives them back emptied with their capacity kept, so that a small request's scratch is
// neither allocated nor grown again. An object holding more than the pool's byte cap is freed
// instead, and at most one per hardware thread is kept, so what is kept stays a few megabytes.
// T::clearKeepingRoom() empties the object and returns the bytes it holds.
// A thread slot (tbb::this_task_arena::current_thread_index()) takes back the object it gave, where
// it can: its memory is then in that core's cache rather than another's (parallel_chunks.h).
#pragma once

#include <algorithm>
#include <cstddef>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace tessera {

template <typename T>
class ScratchPool {
 public:
  // The thread count is read once: glibc reads it from sysfs on every call (open, read, close),
  // which was 3 % of a small request's time when each give() asked.
  explicit ScratchPool(size_t keptBytes)
      : keptBytes_(keptBytes), keptObjects_(std::max(1u, std::thread::hardware_concurrency())) {}

  std::unique_ptr<T> take(int slot = -1) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (!free_.empty()) {
        const auto own = std::find_if(free_.rbegin(), free_.rend(), [slot](const Kept& k) { return k.slot == slot; });
        const auto pick = own != free_.rend() ? std::prev(own.base()) : std::prev(free_.end());
        std::unique_ptr<T> object = std::move(pick->object);
        free_.erase(pick);
        return object;
      }
    }
    return std::make_unique<T>();
  }

  void give(std::unique_ptr<T> object, int slot = -1) {
    if (!object || object->clearKeepingRoom() > keptBytes_) return;
    const std::lock_guard<std::mutex> lock(mutex_);
    if (free_.size() < keptObjects_) free_.push_back({std::move(object), slot});
  }

 private:
  const size_t keptBytes_;
  const size_t keptObjects_;
  std::mutex mutex_;
  struct Kept {
    std::unique_ptr<T> object;
    int slot;
  };
  std::vector<Kept> free_;
};

}  // namespace tessera
