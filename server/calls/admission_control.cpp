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

AdmissionControl::Slot::Slot(AdmissionControl* owner, const CancellationToken* cancel, int64_t bytes,
                             AdmissionLane lane)
    : owner_(owner), cancel_(cancel), bytes_(bytes), lane_(lane), start_(std::chrono::steady_clock::now()) {}

AdmissionControl::Slot::Slot(Slot&& other) noexcept
    : owner_(std::exchange(other.owner_, nullptr)),
      cancel_(other.cancel_),
      bytes_(std::exchange(other.bytes_, 0)),
      lane_(other.lane_),
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

AdmissionControl::AdmissionControl(int maxRunning, int maxQueued, int64_t memoryBytes, std::string memoryNote,
                                   int maxLightRunning)
    : lanes_{Lane(std::max(maxRunning, 1)), Lane(std::max(maxLightRunning > 0 ? maxLightRunning : maxRunning, 1))},
      lightLane_(maxLightRunning >= 0),
      maxQueued_(std::max(maxQueued, 0)),
      memory_(std::max<int64_t>(memoryBytes, 0)),
      memoryNote_(std::move(memoryNote)) {}

bool AdmissionControl::mayStartLocked(uint64_t ticket, AdmissionLane which) const {
  const Lane& l = lane(which);
  return l.running < l.maxRunning && !growingAheadLocked(which) && !l.waiting.empty() &&
         l.waiting.front().ticket == ticket && reserved_ + l.waiting.front().bytes <= memory_;
}

bool AdmissionControl::growingAheadLocked(AdmissionLane which) const {
  // Main jobs already running that wait for more memory go before new main jobs (else a stream
  // of new ones could starve them); a light job takes little and ends soon, so it goes on.
  return which == AdmissionLane::kMain && growing_ > 0;
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
                                                 std::string_view what, AdmissionLane which) {
  bytes = std::max<int64_t>(bytes, 0);
  if (!lightLane_) which = AdmissionLane::kMain;
  std::unique_lock lock(mutex_);
  if (bytes > memory_) {
    ++rejected_;
    requireFits(bytes, what);
  }
  Lane& l = lane(which);
  auto start = [&] {
    ++l.running;
    ++running_;
    reserved_ += bytes;
    return Slot(this, &cancel, bytes, which);
  };
  if (l.running < l.maxRunning && l.waiting.empty() && !growingAheadLocked(which) && reserved_ + bytes <= memory_) {
    return start();
  }
  if (static_cast<int>(l.waiting.size()) >= maxQueued_) {
    ++rejected_;
    int64_t retryAfter = retryAfterMsLocked(which);
    throw StatusError(grpc::StatusCode::RESOURCE_EXHAUSTED,
                      fmt::format("server busy: {} jobs running and {} queued{} (the limits); "
                                  "retry after {} ms",
                                  l.running, l.waiting.size(), which == AdmissionLane::kLight ? " in the light lane" : "",
                                  retryAfter),
                      retryAfter);
  }
  uint64_t ticket = nextTicket_++;
  auto mine = l.waiting.insert(l.waiting.end(), Waiting{ticket, bytes});
  // Leaving the queue early must also let the next in line move to the front.
  auto leave = [&] {
    l.waiting.erase(mine);
    changed_.notify_all();
  };
  if (onQueued) {
    int position = static_cast<int>(l.waiting.size());
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
  while (!mayStartLocked(ticket, which)) {
    if (cancel.cancelled()) {
      leave();
      throw OperationCancelled();
    }
    changed_.wait_for(lock, kCancelPollInterval);
  }
  l.waiting.erase(mine);
  changed_.notify_all();
  return start();
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
      const int64_t retryAfter = retryAfterMsLocked(slot.lane_);
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
  Lane& l = lane(slot.lane_);
  --l.running;
  --running_;
  reserved_ -= slot.bytes_;
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - slot.start_).count();
  l.typicalJobSeconds = 0.8 * l.typicalJobSeconds + 0.2 * seconds;
  changed_.notify_all();
}

int64_t AdmissionControl::retryAfterMsLocked(AdmissionLane which) const {
  // Roughly when a queue slot frees: the jobs ahead, spread over the lane's running slots.
  const Lane& l = lane(which);
  double ahead = static_cast<double>(l.waiting.size() + 1) / l.maxRunning;
  auto ms = static_cast<int64_t>(std::ceil(1000.0 * l.typicalJobSeconds * ahead));
  return std::clamp(ms, kMinRetryAfterMs, kMaxRetryAfterMs);
}

int AdmissionControl::running() const {
  std::lock_guard lock(mutex_);
  return running_;
}

int AdmissionControl::queued() const {
  std::lock_guard lock(mutex_);
  return static_cast<int>(lanes_[0].waiting.size() + lanes_[1].waiting.size());
}

int AdmissionControl::running(AdmissionLane which) const {
  std::lock_guard lock(mutex_);
  return lane(which).running;
}

int AdmissionControl::queued(AdmissionLane which) const {
  std::lock_guard lock(mutex_);
  return static_cast<int>(lane(which).waiting.size());
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
