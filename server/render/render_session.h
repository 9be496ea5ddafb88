// The two halves of a RenderSession call. A reader thread takes camera updates off the stream
// as fast as they come, checks them, and posts each into a LatestCameraMailbox, which holds only
// the newest camera not yet drawn; the call's own thread takes cameras out one at a time and
// renders them. A client that moves the camera faster than the server renders therefore gets
// the newest view next, never a backlog of stale ones (the frames' sequence numbers skip).
#pragma once

#include <grpcpp/grpcpp.h>

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>

#include "server/calls/cancellation.h"
#include "server/render/render_backend.h"
#include "server/calls/status_error.h"
#include "server/calls/stream_watch.h"
#include "server/calls/accuracy_limits.h"
#include "tessera/v1/render.grpc.pb.h"

namespace tessera::server {

struct PendingCamera {
  uint64_t sequence = 0;
  Camera camera;
};

class LatestCameraMailbox {
 public:
  // Reader side. post() replaces a camera not yet taken (which counts as dropped); finish()
  // says no more cameras will come; fail() ends the session with error (pending cameras are
  // dropped) and implies finish().
  void post(const PendingCamera& camera);
  void finish();
  void fail(const StatusError& error);

  // Renderer side: the newest camera not yet drawn, waiting for one if needed; nullopt once
  // the reader has finished and nothing is pending, or has failed. Polls cancel while waiting
  // (OperationCancelled).
  std::optional<PendingCamera> next(const CancellationToken& cancel);

  bool finished() const;
  std::optional<StatusError> failure() const;
  uint64_t received() const;
  uint64_t dropped() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::optional<PendingCamera> pending_;
  bool finished_ = false;
  std::optional<StatusError> failure_;
  uint64_t received_ = 0;
  uint64_t dropped_ = 0;
};

using SessionStream =
    grpc::ServerReaderWriter<tessera::v1::SessionResponse, tessera::v1::SessionRequest>;

// The reader thread's body: reads the messages after the SessionStart until the client
// half-closes or the call ends, numbers and checks each camera (render_request.h) and posts it.
// A malformed message fails the mailbox with INVALID_ARGUMENT naming the update and stops
// reading. Always finishes the mailbox; never throws.
void readCameraUpdates(Watched<SessionStream>& stream, const FrameSettings& settings,
                       const TessellationLimits& limits, LatestCameraMailbox& mailbox) noexcept;

}  // namespace tessera::server
