// At most one build of a value per key at a time (the shape of Go's singleflight, with
// cancellation): a call that finds a build of its key under way waits for it instead of starting
// its own, so concurrent cold requests for one mesh preprocess it once.
//
// Whose failure is whose: the build runs in the call that started it, with that call's
// cancellation and memory reservation. A failure of type KeyError (for the patch-set cache,
// core's TesseraError: bad or unsupported input, a refinement over the server's limit) belongs to
// the key, since every build of it would meet it, and every waiter gets it too. Anything else the
// build throws (its call cancelled or past its deadline, its memory refused, an unexpected error)
// belongs to that call alone: the waiters wake and try again, and one of them builds. Each call
// so builds at most once, and a waiter stops waiting, with OperationCancelled, when its own call
// is cancelled.
#pragma once

#include <chrono>
#include <exception>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <utility>

#include "server/calls/cancellation.h"
#include "server/calls/memory_reservation.h"

namespace tessera::server {

template <typename Key, typename Value, typename KeyError, typename Hash = std::hash<Key>>
class SingleFlight {
 public:
  using ValuePtr = std::shared_ptr<const Value>;

  // The value for `key`: what `find()` returns when not null (it runs under the flights' lock, so
  // it never looks between another call's build storing its value and that build ending), else
  // the value of the build of `key` under way, waited for, else what `build()` returns, run in
  // this thread. `build` stores its value where `find` looks before it returns. `memory` (may be
  // null) is the calling job's reservation, marked as waiting for another job while it waits.
  // Throws what `build` throws (a KeyError also when another call's build threw it), and
  // OperationCancelled when `cancel` fires while waiting.
  template <typename Find, typename Build>
  ValuePtr get(const Key& key, const CancellationToken& cancel, MemoryReservation* memory,
               Find&& find, Build&& build) {
    for (;;) {
      std::unique_lock lock(mutex_);
      if (ValuePtr found = find()) return found;
      if (auto it = flights_.find(key); it != flights_.end()) {
        std::shared_future<ValuePtr> flight = it->second;
        lock.unlock();
        if (ValuePtr built = waitFor(flight, cancel, memory)) return built;
        continue;  // its builder's call gave up: look again, and build if no one else has started
      }
      std::promise<ValuePtr> promise;
      flights_.emplace(key, promise.get_future().share());
      lock.unlock();
      return buildAs(key, promise, build);
    }
  }

  // Builds under way.
  size_t inFlight() const {
    std::lock_guard lock(mutex_);
    return flights_.size();
  }

 private:
  // How often a waiter looks at its cancellation token (the server's other waits poll as often).
  static constexpr auto kCancelPoll = std::chrono::milliseconds(20);

  // The flight's value; null when its builder's call gave up. Rethrows the key's failure.
  static ValuePtr waitFor(const std::shared_future<ValuePtr>& flight,
                          const CancellationToken& cancel, MemoryReservation* memory) {
    MemoryReservation::WaitingForAnotherJob waiting(memory);
    while (flight.wait_for(kCancelPoll) != std::future_status::ready) cancel.throwIfCancelled();
    return flight.get();
  }

  template <typename Build>
  ValuePtr buildAs(const Key& key, std::promise<ValuePtr>& promise, Build& build) {
    ValuePtr value;
    try {
      value = build();
    } catch (const KeyError&) {
      land(key);
      promise.set_exception(std::current_exception());
      throw;
    } catch (...) {
      land(key);
      promise.set_value(nullptr);
      throw;
    }
    land(key);
    promise.set_value(value);
    return value;
  }

  // The flight ends: calls from now on find the value where `build` stored it, or build again.
  void land(const Key& key) {
    std::lock_guard lock(mutex_);
    flights_.erase(key);
  }

  mutable std::mutex mutex_;
  std::unordered_map<Key, std::shared_future<ValuePtr>, Hash> flights_;
};

}  // namespace tessera::server
