#include "server/store/store_health.h"

#include <spdlog/spdlog.h>

namespace tessera::server {

StoreHealth::StoreHealth(MeshStore& store, std::function<void(bool)> setServing, Timing timing)
    : store_(store), setServing_(std::move(setServing)), timing_(timing) {
  // The first probe counts as running from now, so that the watcher never reports on none.
  probing_ = true;
  probeStart_ = Clock::now();
  prober_ = std::thread([this] { probeLoop(); });
  watcher_ = std::thread([this] { watchLoop(); });
}

StoreHealth::~StoreHealth() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  watcher_.join();
  prober_.join();
}

void StoreHealth::probeLoop() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    probing_ = true;
    probeStart_ = Clock::now();
    lock.unlock();
    bool ok = true;
    std::string cause;
    try {
      store_.probe();
    } catch (const std::exception& e) {
      ok = false;
      cause = e.what();
    }
    lock.lock();
    probing_ = false;
    lastProbeOk_ = ok;
    lastCause_ = std::move(cause);
    wake_.notify_all();
    wake_.wait_for(lock, timing_.interval, [this] { return stopping_; });
  }
}

// Wakes after every probe and, while one runs, often enough to call it hung on time.
void StoreHealth::watchLoop() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    if (probing_ && Clock::now() - probeStart_ > timing_.timeout) {
      const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(timing_.timeout).count();
      publish(false, "no answer to a probe within " + std::to_string(ms) + " ms");
    } else if (!probing_) {
      publish(lastProbeOk_, lastCause_);
    }
    wake_.wait_for(lock, timing_.timeout / 4, [this] { return stopping_; });
  }
}

void StoreHealth::publish(bool serving, const std::string& cause) {
  if (published_ == int(serving)) return;
  if (serving) {
    spdlog::info("mesh store answers: health SERVING");
  } else {
    spdlog::warn("mesh store cannot serve ({}): health NOT_SERVING", cause);
  }
  published_ = int(serving);
  setServing_(serving);
}

}  // namespace tessera::server
