// Admission control for heavy jobs (validating an upload, tessellating, drawing): at most
// maxRunning run at once and at most maxQueued wait, first come first served. Past that the
// server refuses at once with RESOURCE_EXHAUSTED and a retry hint instead of letting latency
// grow without bound; this is what keeps a 2-core box responsive under a burst.
//
// Jobs come in two lanes, each with its own slots and its own queue (server/README.md,
// Scheduling by cost): the main lane, and a light lane for jobs known before they start to be
// short (a small upload, a tessellation of a mesh already preprocessed whose estimated output is
// small, job_cost.h). A light job never waits behind a long one for a slot: with every main slot
// held for minutes, the light lane still turns over in milliseconds. Both lanes share the memory.
//
// Memory is admitted the same way, in bytes: the jobs together hold at most `memoryBytes`
// (the server's --memory-budget less its caches). A job starts only when what it reserves up
// front fits beside the others', and reserves more as it learns its size (MemoryReservation).
// A reservation that could never fit is refused at once, naming the estimate and the budget.
// One that fits once others finish waits for them; if every other running job is itself
// waiting (for memory, or for work another job does for it), it is refused with a retry hint
// instead (no two jobs wait on each other).
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <list>
#include <utility>
#include <mutex>
#include <string>
#include <string_view>

#include "server/calls/cancellation.h"
#include "server/calls/memory_reservation.h"

namespace tessera::server {

// Which slots and queue a job takes (see above).
enum class AdmissionLane { kMain = 0, kLight = 1 };

class AdmissionControl {
 public:
  static constexpr int64_t kUnlimited = INT64_MAX / 4;

  // Holding a Slot means the job may run; destroying it lets the next one in and gives its
  // memory back. Not movable once the job has a pointer to it.
  class Slot : public MemoryReservation {
   public:
    Slot(Slot&& other) noexcept;
    Slot& operator=(Slot&&) = delete;
    ~Slot() override;
    void reserve(int64_t bytes, std::string_view what) override;
    void release(int64_t bytes) override;
    int64_t reserved() const { return bytes_; }

   protected:
    void beginWaitingForAnotherJob() override;
    void endWaitingForAnotherJob() override;

   private:
    friend class AdmissionControl;
    Slot(AdmissionControl* owner, const CancellationToken* cancel, int64_t bytes, AdmissionLane lane);
    AdmissionControl* owner_;
    const CancellationToken* cancel_;
    int64_t bytes_;
    AdmissionLane lane_;
    std::chrono::steady_clock::time_point start_;
  };

  // memoryBytes: what the jobs together may reserve; memoryNote, how the server came to it
  // (for messages, e.g. "--memory-budget 6 GiB less the caches' 1 GiB"). maxRunning and
  // maxQueued are the main lane's; the light lane has maxLightRunning slots (0: as many as the
  // main lane; negative: no light lane, its jobs go to the main lane) and a queue as deep.
  AdmissionControl(int maxRunning, int maxQueued, int64_t memoryBytes = kUnlimited,
                   std::string memoryNote = "", int maxLightRunning = 0);

  // Waits for a slot, and for `bytes` of memory for `what`, while polling cancel.
  // onQueued(position) runs once, before waiting, when the job has to wait (position 1 = next).
  // Throws StatusError(RESOURCE_EXHAUSTED, with retryAfterMs) when the queue is full,
  // RESOURCE_EXHAUSTED without a retry hint when `bytes` exceed the whole budget, and
  // OperationCancelled when cancelled while waiting. `cancel` must outlive the slot. The job
  // waits in `lane` only: behind the jobs queued there, for that lane's slots.
  Slot acquire(const CancellationToken& cancel, const std::function<void(int position)>& onQueued = {},
               int64_t bytes = 0, std::string_view what = "the job", AdmissionLane lane = AdmissionLane::kMain);

  // Jobs running and waiting in both lanes, or in one.
  int running() const;
  int queued() const;
  int running(AdmissionLane lane) const;
  int queued(AdmissionLane lane) const;
  int maxRunning() const { return lanes_[0].maxRunning; }
  int maxLightRunning() const { return lanes_[1].maxRunning; }
  int maxQueued() const { return maxQueued_; }
  uint64_t rejected() const;
  int64_t memoryBudget() const { return memory_; }
  int64_t memoryReserved() const;
  // Throws what acquire() throws for `bytes` that could never fit (a check before any work).
  void requireFits(int64_t bytes, std::string_view what) const;

 private:
  void release(const Slot& slot);
  void reserve(Slot& slot, int64_t bytes, std::string_view what);
  void giveBack(Slot& slot, int64_t bytes);
  void waitForAnotherJob(int change);
  int64_t retryAfterMsLocked(AdmissionLane lane) const;
  bool mayStartLocked(uint64_t ticket, AdmissionLane lane) const;
  bool growingAheadLocked(AdmissionLane lane) const;

  struct Waiting {
    uint64_t ticket;
    int64_t bytes;
  };
  struct Lane {
    explicit Lane(int slots) : maxRunning(slots) {}
    int maxRunning;
    int running = 0;
    std::list<Waiting> waiting;       // in arrival order
    double typicalJobSeconds = 1.0;   // moving average, for the retry hint
  };
  Lane& lane(AdmissionLane which) { return lanes_[static_cast<int>(which)]; }
  const Lane& lane(AdmissionLane which) const { return lanes_[static_cast<int>(which)]; }

  Lane lanes_[2];
  const bool lightLane_;
  const int maxQueued_;
  const int64_t memory_;
  const std::string memoryNote_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  int running_ = 0;             // in both lanes
  int growing_ = 0;             // running jobs waiting in reserve()
  int waitingForOthers_ = 0;    // running jobs waiting for work another job does for them
  int64_t reserved_ = 0;        // bytes held by running jobs
  uint64_t nextTicket_ = 0;
  uint64_t rejected_ = 0;
};

// "1.5 GiB", "300 MiB", "12 KiB": sizes in messages.
std::string formatBytes(int64_t bytes);

}  // namespace tessera::server
