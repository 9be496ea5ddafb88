// Admission control for heavy jobs (validating an upload, tessellating): at most maxRunning run
// at once and at most maxQueued wait, first come first served. Past that the server refuses at
// once with RESOURCE_EXHAUSTED and a retry hint instead of letting latency and memory grow
// without bound; this is what keeps a 2-core box responsive under a burst.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <list>
#include <utility>
#include <mutex>

#include "server/cancellation.h"

namespace tessera::server {

class AdmissionControl {
 public:
  // Holding a Slot means the job may run; destroying it lets the next one in.
  class Slot {
   public:
    Slot(Slot&& other) noexcept;
    Slot& operator=(Slot&&) = delete;
    ~Slot();

   private:
    friend class AdmissionControl;
    explicit Slot(AdmissionControl* owner);
    AdmissionControl* owner_;
    std::chrono::steady_clock::time_point start_;
  };

  AdmissionControl(int maxRunning, int maxQueued);

  // Waits for a slot while polling cancel. onQueued(position) runs once, before waiting, when
  // the job has to wait (position 1 = next). Throws StatusError(RESOURCE_EXHAUSTED, with
  // retryAfterMs) when the queue is full, OperationCancelled when cancelled while waiting.
  Slot acquire(const CancellationToken& cancel,
               const std::function<void(int position)>& onQueued = {});

  int running() const;
  int queued() const;
  int maxRunning() const { return maxRunning_; }
  int maxQueued() const { return maxQueued_; }
  uint64_t rejected() const;

 private:
  void release(std::chrono::steady_clock::duration ran);
  int64_t retryAfterMsLocked() const;
  bool mayStartLocked(uint64_t ticket) const;

  const int maxRunning_;
  const int maxQueued_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  int running_ = 0;
  std::list<uint64_t> waiting_;  // tickets in arrival order
  uint64_t nextTicket_ = 0;
  uint64_t rejected_ = 0;
  double typicalJobSeconds_ = 1.0;  // moving average, for the retry hint
};

}  // namespace tessera::server
