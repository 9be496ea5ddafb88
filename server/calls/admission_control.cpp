#include "server/calls/admission_control.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "server/calls/status_error.h"

namespace tessera::server {
namespace {

// How often a waiting job looks at its cancellation token: short enough that a cancelled or
// expired call leaves the queue promptly, long enough to cost nothing.
constexpr auto kCancelPollInterval = std::chrono::milliseconds(20);
constexpr int64_t kMinRetryAfterMs = 100;
constexpr int64_t kMaxRetryAfterMs = 60'000;

}  // namespace

AdmissionControl::Slot::Slot(AdmissionControl* owner, const CancellationToken* cancel, int64_t bytes)
    : owner_(owner), cancel_(cancel), bytes_(bytes), start_(std::chrono::steady_clock::now()) {}

AdmissionControl::Slot::Slot(Slot&& other) noexcept
    : owner_(std::exchange(other.owner_, nullptr)),
      cancel_(other.cancel_),
      bytes_(std::exchange(other.bytes_, 0)),
      start_(other.start_) {}

AdmissionControl::Slot::~Slot() {
  if (owner_) owner_->release(*this);
}

void AdmissionControl::Slot::reserve(int64_t bytes, std::string_view what) {
  if (owner_ && bytes > 0) owner_->reserve(*this, bytes, what);
}

void AdmissionControl::Slot::release(int64_t bytes) {
  if (owner_ && bytes > 0) owner_->giveBack(*this, bytes);
}

void AdmissionControl::Slot::beginWaitingForAnotherJob() {
  if (owner_) owner_->waitForAnotherJob(+1);
}

void AdmissionControl::Slot::endWaitingForAnotherJob() {
  if (owner_) owner_->waitForAnotherJob(-1);
}

AdmissionControl::AdmissionControl(int maxRunning, int maxQueued, int64_t memoryBytes, std::string memoryNote)
    : maxRunning_(std::max(maxRunning, 1)),
      maxQueued_(std::max(maxQueued, 0)),
      memory_(std::max<int64_t>(memoryBytes, 0)),
      memoryNote_(std::move(memoryNote)) {}

bool AdmissionControl::mayStartLocked(uint64_t ticket) const {
  // Jobs already running that wait for more memory go first.
  return running_ < maxRunning_ && growing_ == 0 && !waiting_.empty() && waiting_.front().ticket == ticket &&
         reserved_ + waiting_.front().bytes <= memory_;
}

void AdmissionControl::requireFits(int64_t bytes, std::string_view what) const {
  if (bytes <= memory_) return;
  throw StatusError(grpc::StatusCode::RESOURCE_EXHAUSTED,
                    fmt::format("{} needs about {} of memory, over the server's memory budget for jobs of {}{}",
                                what, formatBytes(bytes), formatBytes(memory_),
                                memoryNote_.empty() ? "" : " (" + memoryNote_ + ")"));
}

AdmissionControl::Slot AdmissionControl::acquire(const CancellationToken& cancel,
                                                 const std::function<void(int)>& onQueued, int64_t bytes,
                                                 std::string_view what) {
  bytes = std::max<int64_t>(bytes, 0);
  std::unique_lock lock(mutex_);
  if (bytes > memory_) {
    ++rejected_;
    requireFits(bytes, what);
  }
  if (running_ < maxRunning_ && waiting_.empty() && growing_ == 0 && reserved_ + bytes <= memory_) {
    ++running_;
    reserved_ += bytes;
    return Slot(this, &cancel, bytes);
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
  auto mine = waiting_.insert(waiting_.end(), Waiting{ticket, bytes});
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
  reserved_ += bytes;
  changed_.notify_all();
  return Slot(this, &cancel, bytes);
}

void AdmissionControl::reserve(Slot& slot, int64_t bytes, std::string_view what) {
  std::unique_lock lock(mutex_);
  if (slot.bytes_ + bytes > memory_) {
    ++rejected_;
    throw StatusError(grpc::StatusCode::RESOURCE_EXHAUSTED,
                      fmt::format("{} needs about {} of memory; with the {} the job already holds that is over "
                                  "the server's memory budget for jobs of {}{}",
                                  what, formatBytes(bytes), formatBytes(slot.bytes_), formatBytes(memory_),
                                  memoryNote_.empty() ? "" : " (" + memoryNote_ + ")"));
  }
  ++growing_;
  auto stopGrowing = [&] {
    --growing_;
    changed_.notify_all();
  };
  while (reserved_ + bytes > memory_) {
    if (slot.cancel_->cancelled()) {
      stopGrowing();
      throw OperationCancelled();
    }
    // Only a running job that is not itself waiting can give memory back.
    if (running_ - growing_ - waitingForOthers_ <= 0) {
      stopGrowing();
      ++rejected_;
      const int64_t retryAfter = retryAfterMsLocked();
      throw StatusError(grpc::StatusCode::RESOURCE_EXHAUSTED,
                        fmt::format("{} needs about {} of memory and other jobs hold {} of the server's memory "
                                    "budget for jobs of {}; retry after {} ms",
                                    what, formatBytes(bytes), formatBytes(reserved_ - slot.bytes_),
                                    formatBytes(memory_), retryAfter),
                        retryAfter);
    }
    changed_.wait_for(lock, kCancelPollInterval);
  }
  reserved_ += bytes;
  slot.bytes_ += bytes;
  stopGrowing();
}

void AdmissionControl::giveBack(Slot& slot, int64_t bytes) {
  std::lock_guard lock(mutex_);
  bytes = std::min(bytes, slot.bytes_);
  slot.bytes_ -= bytes;
  reserved_ -= bytes;
  changed_.notify_all();
}

void AdmissionControl::waitForAnotherJob(int change) {
  std::lock_guard lock(mutex_);
  waitingForOthers_ += change;
  changed_.notify_all();  // a job growing meanwhile looks again at who could give memory back
}

void AdmissionControl::release(const Slot& slot) {
  std::lock_guard lock(mutex_);
  --running_;
  reserved_ -= slot.bytes_;
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - slot.start_).count();
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

int64_t AdmissionControl::memoryReserved() const {
  std::lock_guard lock(mutex_);
  return reserved_;
}

std::string formatBytes(int64_t bytes) {
  constexpr const char* kUnits[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
  double value = double(bytes);
  int unit = 0;
  while (value >= 1024 && unit < 4) value /= 1024, ++unit;
  if (unit == 0) return fmt::format("{} bytes", bytes);
  return value < 10 ? fmt::format("{:.1f} {}", value, kUnits[unit]) : fmt::format("{:.0f} {}", value, kUnits[unit]);
}

}  // namespace tessera::server
