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
};

}  // namespace tessera::server
