#include "server/calls/stream_watch.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>

#include "server/calls/status_error.h"

namespace tessera::server {

namespace {

double seconds(StreamWatch::Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// Whether a wait that began at `since` (0: none under way) has lasted longer than limit.
bool overdue(const std::atomic<int64_t>& since, StreamWatch::Clock::duration limit, StreamWatch::Clock::time_point now) {
  const int64_t start = since.load();
  return start != 0 && now - StreamWatch::Clock::time_point(StreamWatch::Clock::duration(start)) > limit;
}

}  // namespace

StreamWatch::StreamWatch(Limits limits) : limits_(limits) {
  watchdog_ = std::thread([this] { watch(); });
}

StreamWatch::~StreamWatch() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  stop_.notify_all();
  watchdog_.join();
}

StreamWatch::Call::~Call() {
  if (owner_ == nullptr) return;
  std::lock_guard lock(owner_->mutex_);
  owner_->open_.erase(entry_);
}

StreamWatch::Call StreamWatch::open(grpc::ServerContext& context, const std::string& method, bool session) {
  std::lock_guard lock(mutex_);
  if (int(open_.size()) >= limits_.maxOpen) {
    throw StatusError(grpc::StatusCode::RESOURCE_EXHAUSTED,
                      fmt::format("the server has {} streaming calls open, its limit; retry later", limits_.maxOpen),
                      1000);
  }
  open_.emplace_back();
  Entry& entry = open_.back();
  entry.context = &context;
  entry.method = method;
  entry.readLimit = session ? limits_.sessionIdle : limits_.idle;
  return Call(this, std::prev(open_.end()));
}

int StreamWatch::openCalls() const {
  std::lock_guard lock(mutex_);
  return int(open_.size());
}

uint64_t StreamWatch::cancelledCalls() const {
  std::lock_guard lock(mutex_);
  return cancelled_;
}

// Looks often enough to cancel within a quarter of the shortest limit past it (at most 1 s).
void StreamWatch::watch() {
  const Clock::duration tick = std::min<Clock::duration>(std::chrono::seconds(1), std::min(limits_.idle, limits_.sessionIdle) / 4);
  std::unique_lock lock(mutex_);
  while (!stop_.wait_for(lock, tick, [this] { return stopping_; })) {
    const Clock::time_point now = Clock::now();
    for (Entry& entry : open_) {
      const bool reading = overdue(entry.readSince, entry.readLimit, now);
      if (!reading && !overdue(entry.writeSince, limits_.idle, now)) continue;
      spdlog::warn("{} from {}: the client {} for {:.0f} s: call cancelled", entry.method, entry.context->peer(),
                   reading ? "sent nothing" : "read nothing", seconds(reading ? entry.readLimit : limits_.idle));
      entry.context->TryCancel();
      // Counted once: the waits it was cancelled in end, and a cancelled call waits no more.
      entry.readSince.store(0);
      entry.writeSince.store(0);
      ++cancelled_;
    }
  }
}

}  // namespace tessera::server
