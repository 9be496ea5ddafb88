#include "server/render/render_session.h"

#include <fmt/format.h>

#include <chrono>

#include "server/render/render_request.h"

namespace tessera::server {
namespace {

namespace v1 = tessera::v1;

// How often a renderer waiting for a camera checks whether its call was cancelled.
constexpr auto kCancelPoll = std::chrono::milliseconds(20);

}  // namespace

void LatestCameraMailbox::post(const PendingCamera& camera) {
  {
    std::lock_guard lock(mutex_);
    if (finished_) return;
    if (pending_) ++dropped_;
    pending_ = camera;
    ++received_;
  }
  changed_.notify_all();
}

void LatestCameraMailbox::finish() {
  {
    std::lock_guard lock(mutex_);
    finished_ = true;
  }
  changed_.notify_all();
}

void LatestCameraMailbox::fail(const StatusError& error) {
  {
    std::lock_guard lock(mutex_);
    if (!failure_) failure_ = error;
    if (pending_) ++dropped_;
    pending_.reset();
    finished_ = true;
  }
  changed_.notify_all();
}

std::optional<PendingCamera> LatestCameraMailbox::next(const CancellationToken& cancel) {
  std::unique_lock lock(mutex_);
  for (;;) {
    if (failure_) return std::nullopt;
    if (pending_) {
      std::optional<PendingCamera> taken = std::move(pending_);
      pending_.reset();
      return taken;
    }
    if (finished_) return std::nullopt;
    changed_.wait_for(lock, kCancelPoll);
    if (cancel.cancelled()) throw OperationCancelled();
  }
}

bool LatestCameraMailbox::finished() const {
  std::lock_guard lock(mutex_);
  return finished_;
}

std::optional<StatusError> LatestCameraMailbox::failure() const {
  std::lock_guard lock(mutex_);
  return failure_;
}

uint64_t LatestCameraMailbox::received() const {
  std::lock_guard lock(mutex_);
  return received_;
}

uint64_t LatestCameraMailbox::dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

void readCameraUpdates(Watched<SessionStream>& stream, const FrameSettings& settings,
                       const TessellationLimits& limits, LatestCameraMailbox& mailbox) noexcept {
  try {
    v1::SessionRequest message;
    uint64_t last = 0;
    // Message 1 was the SessionStart.
    for (int64_t position = 2; stream.Read(&message); ++position) {
      if (message.has_start()) {
        throwInvalidArgument(
            fmt::format("message {}: start: only the first message may be a "
                        "SessionStart",
                        position));
      }
      if (!message.has_camera()) {
        throwInvalidArgument(
            fmt::format("message {}: carries neither a start nor a camera", position));
      }
      const v1::CameraUpdate& update = message.camera();
      uint64_t sequence = update.sequence() > 0 ? update.sequence() : last + 1;
      if (sequence <= last) {
        throwInvalidArgument(
            fmt::format("message {}: camera.sequence {} must be larger than the "
                        "previous update's ({})",
                        position, sequence, last));
      }
      if (!update.has_camera()) {
        throwInvalidArgument(fmt::format("camera[sequence {}]: is required", sequence));
      }
      PendingCamera pending;
      pending.sequence = sequence;
      pending.camera = checkRenderCamera(
          update.camera(), fmt::format("camera[sequence {}]", sequence), settings, limits);
      last = sequence;
      mailbox.post(pending);
    }
    mailbox.finish();
  } catch (const StatusError& error) {
    mailbox.fail(error);
  } catch (const std::exception& error) {
    mailbox.fail(StatusError(grpc::StatusCode::INTERNAL,
                             std::string("internal error reading the session: ") + error.what()));
  } catch (...) {
    mailbox.fail(StatusError(grpc::StatusCode::INTERNAL, "internal error reading the session"));
  }
}

}  // namespace tessera::server
