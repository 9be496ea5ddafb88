// A gate a test opens once, for tests that hold a build or a call at a chosen point (the
// patch-set cache's and single flight's): waiting for it never takes more than 10 s, so a test
// that would hang fails instead.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>

namespace tessera::test {

class Gate {
 public:
  void open() {
    std::lock_guard lock(mutex_);
    open_ = true;
    opened_.notify_all();
  }
  bool wait() {
    std::unique_lock lock(mutex_);
    return opened_.wait_for(lock, std::chrono::seconds(10), [&] { return open_; });
  }

 private:
  std::mutex mutex_;
  std::condition_variable opened_;
  bool open_ = false;
};

}  // namespace tessera::test
