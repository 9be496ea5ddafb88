// The health service follows the store: a prober reads the store every interval, and the server
// reports NOT_SERVING while the last probe failed or one has been running longer than the timeout
// (a store that hangs is as unable to serve as one that refuses), SERVING again once a probe
// succeeds. Transitions are logged with the cause.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "server/store/mesh_store.h"

namespace tessera::server {

class StoreHealth {
 public:
  using Clock = std::chrono::steady_clock;
  struct Timing {
    Clock::duration interval = std::chrono::seconds(1);
    // Longer than a large upload holds SQLite's lock: a busy store is not a failed one.
    Clock::duration timeout = std::chrono::seconds(5);
  };

  // setServing is called on every change of the verdict, and first with the initial one.
  StoreHealth(MeshStore& store, std::function<void(bool serving)> setServing, Timing timing);
  StoreHealth(const StoreHealth&) = delete;
  StoreHealth& operator=(const StoreHealth&) = delete;
  // Stops both threads (waiting for a probe in flight).
  ~StoreHealth();

 private:
  void probeLoop();
  void watchLoop();
  void publish(bool serving, const std::string& cause);

  MeshStore& store_;
  std::function<void(bool)> setServing_;
  Timing timing_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  bool lastProbeOk_ = false;
  std::string lastCause_;
  bool probing_ = false;
  Clock::time_point probeStart_;
  int published_ = -1;  // the verdict last passed to setServing (-1: none yet)
  std::thread prober_, watcher_;
};

}  // namespace tessera::server
