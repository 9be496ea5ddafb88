// What a running job may take in memory. A job reserves the bytes core's estimates give
// (core/pipeline/memory_estimates.h) before it makes something big: preprocessing once the refinement is
// estimated, the output once the plan knows its triangles, a frame's buffers before drawing.
// The server's admission control (admission_control.h) holds the budget the reservations come
// from and gives them back when the job ends.
#pragma once

#include <cstdint>
#include <string_view>

namespace tessera::server {

class MemoryReservation {
 public:
  virtual ~MemoryReservation() = default;
  // Adds `bytes` for `what` (a short phrase for messages, e.g. "the output") to the job's
  // reservation; waits while other jobs hold the memory and can give it back. Throws
  // StatusError(RESOURCE_EXHAUSTED) naming the estimate and the budget when it cannot fit, and
  // OperationCancelled when the job is cancelled while waiting.
  virtual void reserve(int64_t bytes, std::string_view what) = 0;
  // Gives back part of what was reserved (an estimate that turned out high).
  virtual void release(int64_t bytes) = 0;

  // Keeps what the job holds for one part of its work (`held`) at `bytes`: reserves the
  // difference for `what`, or gives back the excess of an estimate that turned out high.
  void hold(int64_t& held, int64_t bytes, std::string_view what) {
    if (bytes > held) reserve(bytes - held, what);
    if (bytes < held) release(held - bytes);
    held = bytes;
  }

  // While the job waits for work another job does for both of them (a patch set that job is
  // building, single_flight.h), it gives no memory back until that work ends. Admission control
  // counts it then as it counts a job waiting for memory, so that the job it waits for is
  // refused with a retry hint rather than left waiting for memory this one holds.
  class WaitingForAnotherJob {
   public:
    explicit WaitingForAnotherJob(MemoryReservation* job) : job_(job) {
      if (job_) job_->beginWaitingForAnotherJob();
    }
    ~WaitingForAnotherJob() {
      if (job_) job_->endWaitingForAnotherJob();
    }
    WaitingForAnotherJob(const WaitingForAnotherJob&) = delete;
    WaitingForAnotherJob& operator=(const WaitingForAnotherJob&) = delete;

   private:
    MemoryReservation* job_;
  };

 protected:
  virtual void beginWaitingForAnotherJob() {}
  virtual void endWaitingForAnotherJob() {}
};

}  // namespace tessera::server
