// A thread-safe least-recently-used cache bounded by bytes, not entries, because its values
// (decoded meshes now, preprocessed patch sets later) differ in size by orders of magnitude.
// Values are shared and immutable: an entry evicted while a job still uses it stays alive until
// the job lets go.
#pragma once

#include <cstddef>
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <utility>

namespace tessera::server {

struct CacheStats {
  uint64_t hits = 0;
  uint64_t misses = 0;
  uint64_t evictions = 0;
  size_t bytes = 0;
  size_t entries = 0;
};

template <typename Key, typename Value, typename Hash = std::hash<Key>>
class LruCache {
 public:
  using ValuePtr = std::shared_ptr<const Value>;

  explicit LruCache(size_t byteBudget) : budget_(byteBudget) {}

  // The cached value, now the most recently used, or null (a miss).
  ValuePtr find(const Key& key) {
    std::lock_guard lock(mutex_);
    auto it = index_.find(key);
    if (it == index_.end()) {
      ++stats_.misses;
      return nullptr;
    }
    ++stats_.hits;
    order_.splice(order_.begin(), order_, it->second);
    return it->second->value;
  }

  // Adds or replaces key's value, charged `bytes` against the budget; evicts least recently used
  // entries to make room. A value larger than the whole budget is not cached.
  void insert(const Key& key, ValuePtr value, size_t bytes) {
    std::lock_guard lock(mutex_);
    eraseLocked(key);
    if (bytes > budget_) return;
    while (stats_.bytes + bytes > budget_ && !order_.empty()) {
      Key victim = order_.back().key;  // a copy: erasing destroys the entry that holds it
      eraseLocked(victim);
      ++stats_.evictions;
    }
    order_.push_front(Entry{key, std::move(value), bytes});
    index_.emplace(key, order_.begin());
    stats_.bytes += bytes;
    stats_.entries = order_.size();
  }

  void erase(const Key& key) {
    std::lock_guard lock(mutex_);
    eraseLocked(key);
  }

  CacheStats stats() const {
    std::lock_guard lock(mutex_);
    return stats_;
  }
  size_t byteBudget() const { return budget_; }

 private:
  struct Entry {
    Key key;
    ValuePtr value;
    size_t bytes;
  };

  void eraseLocked(const Key& key) {
    auto it = index_.find(key);
    if (it == index_.end()) return;
    stats_.bytes -= it->second->bytes;
    order_.erase(it->second);
    index_.erase(it);
    stats_.entries = order_.size();
  }

  const size_t budget_;
  mutable std::mutex mutex_;
  std::list<Entry> order_;  // most recently used first
  std::unordered_map<Key, typename std::list<Entry>::iterator, Hash> index_;
  CacheStats stats_;
};

}  // namespace tessera::server
