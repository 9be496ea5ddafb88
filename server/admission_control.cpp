#include "server/admission_control.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "server/status_error.h"

namespace tessera::server {
namespace {

// How often a waiting job looks at its cancellation token: short enough that a cancelled or
// expired call leaves the queue promptly, long enough to cost nothing.
constexpr auto kCancelPollInterval = std::chrono::milliseconds(20);
constexpr int64_t kMinRetryAfterMs = 100;
constexpr int64_t kMaxRetryAfterMs = 60'000;

}  // namespace

AdmissionControl::Slot::Slot(AdmissionControl* owner)
    : owner_(owner), start_(std::chrono::steady_clock::now()) {}

AdmissionControl::Slot::Slot(Slot&& other) noexcept
    : owner_(std::exchange(other.owner_, nullptr)), start_(other.start_) {}

AdmissionControl::Slot::~Slot() {
  if (owner_) owner_->release(std::chrono::steady_clock::now() - start_);
}

AdmissionControl::AdmissionControl(int maxRunning, int maxQueued)
    : maxRunning_(std::max(maxRunning, 1)), maxQueued_(std::max(maxQueued, 0)) {}

bool AdmissionControl::mayStartLocked(uint64_t ticket) const {
  return running_ < maxRunning_ && !waiting_.empty() && waiting_.front() == ticket;
}

AdmissionControl::Slot AdmissionControl::acquire(const CancellationToken& cancel,
                                                 const std::function<void(int)>& onQueued) {
  std::unique_lock lock(mutex_);
  if (running_ < maxRunning_ && waiting_.empty()) {
    ++running_;
    return Slot(this);
  }
  if (static_cast<int>(waiting_.size()) >= maxQueued_) {
    ++rejected_;
    int64_t retryAfter = retryAfterMsLocked();
    throw StatusError(grpc::StatusCode::RESOURCE_EXHAUSTED,
                      fmt::format("server busy: {} jobs running and {} queued (the limits); "
                                  "retry after {} ms",
                                  running_, waiting_.size(), retryAfter),
                      retryAfter);
  }
  uint64_t ticket = nextTicket_++;
  auto mine = waiting_.insert(waiting_.end(), ticket);
  // Leaving the queue early must also let the next in line move to the front.
  auto leave = [&] {
    waiting_.erase(mine);
    changed_.notify_all();
  };
  if (onQueued) {
    int position = static_cast<int>(waiting_.size());
    lock.unlock();
    try {
      onQueued(position);
    } catch (...) {
      lock.lock();
      leave();
      throw;
    }
    lock.lock();
  }
  while (!mayStartLocked(ticket)) {
    if (cancel.cancelled()) {
      leave();
      throw OperationCancelled();
    }
    changed_.wait_for(lock, kCancelPollInterval);
  }
  waiting_.erase(mine);
  ++running_;
  changed_.notify_all();
  return Slot(this);
}

void AdmissionControl::release(std::chrono::steady_clock::duration ran) {
  std::lock_guard lock(mutex_);
  --running_;
  double seconds = std::chrono::duration<double>(ran).count();
  typicalJobSeconds_ = 0.8 * typicalJobSeconds_ + 0.2 * seconds;
  changed_.notify_all();
}

int64_t AdmissionControl::retryAfterMsLocked() const {
  // Roughly when a queue slot frees: the jobs ahead, spread over the running slots.
  double ahead = static_cast<double>(waiting_.size() + 1) / maxRunning_;
  auto ms = static_cast<int64_t>(std::ceil(1000.0 * typicalJobSeconds_ * ahead));
  return std::clamp(ms, kMinRetryAfterMs, kMaxRetryAfterMs);
}

int AdmissionControl::running() const {
  std::lock_guard lock(mutex_);
  return running_;
}

int AdmissionControl::queued() const {
  std::lock_guard lock(mutex_);
  return static_cast<int>(waiting_.size());
}

uint64_t AdmissionControl::rejected() const {
  std::lock_guard lock(mutex_);
  return rejected_;
}

}  // namespace tessera::server
