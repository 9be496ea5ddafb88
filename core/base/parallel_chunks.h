// How finely the adaptive path cuts a loop for TBB: about four chunks a thread. Fixed chunks of
// 16 roots or 256 tiles ran a small request (the creased torus at 1e-3: 32 roots, ~300 tiles) as
// two uneven pieces, so the second core sat out stitching and triangulation; n/64 evened them but,
// on 2 cores, cut the torus into 32 one-root chunks whose steals cost more than they balanced
// (worse when the cores are far apart: bench/machine_load.h). Four a thread is n/64 on 16 cores,
// n/8 on 2; the upper limit keeps large requests' chunks as they were.
#pragma once

#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <memory>

namespace tessera {

// The chunk size for a loop over n items: n / (4 · threads), within [least, most].
inline size_t chunkFor(size_t n, size_t least, size_t most) {
  const size_t parts = 4 * size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
  return std::clamp<size_t>(n / parts, least, most);
}

// Roots (or seam lines) in parts that each thread slot owns, so that a root's tiles, stitching
// and vertices are written and read again by one core in every phase and every call, rather
// than by whichever core stole the chunk. With the two cores far apart (a VM's vCPUs on different
// caches), every line one core wrote that the other then reads or writes costs a round trip of
// ~400 ns: the creased torus at 1e-3 took 0.31 ms a call there against 0.22 ms with the cores
// close, the phases that pass data between cores (stitching, triangulation) up to twice as long;
// owned parts took 3-4 % of the call back there (none close, bigguy ±1 %). At least four parts a
// thread, of at most `most` items (as chunkFor), owned in contiguous runs: slot s owns parts
// [s · parts / threads, (s + 1) · parts / threads). A thread done with its own takes what is left
// of the others', from the far end.
inline size_t ownedParts(size_t n, size_t most) {
  const size_t threads = size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
  return std::min(n, std::max(4 * threads, (n + most - 1) / most));
}

// The ownedParts(n, most) parts of one step, each run once by whichever thread claims it first.
class OwnedPartClaims {
 public:
  OwnedPartClaims(size_t n, size_t most)
      : n_(n), threads_(size_t(std::max(1, tbb::this_task_arena::max_concurrency()))),
        parts_(ownedParts(n, most)), taken_(new std::atomic<bool>[parts_]) {
    for (size_t p = 0; p < parts_; ++p) taken_[p].store(false, std::memory_order_relaxed);
  }
  size_t parts() const { return parts_; }
  // The parallel region's tasks: one a thread.
  size_t tasks() const { return std::min(threads_, parts_); }

  // body(part, first, last) on the calling slot's own parts, then on any left, from the far end.
  template <typename Body>
  void run(const Body& body) {
    const size_t slot = size_t(std::max(0, tbb::this_task_arena::current_thread_index())) % threads_;
    for (size_t p = slot * parts_ / threads_; p < (slot + 1) * parts_ / threads_; ++p) claim(p, body);
    for (size_t p = parts_; p-- > 0;) claim(p, body);
  }

 private:
  template <typename Body>
  void claim(size_t p, const Body& body) {
    if (!taken_[p].exchange(true, std::memory_order_acq_rel)) body(p, p * n_ / parts_, (p + 1) * n_ / parts_);
  }

  size_t n_, threads_, parts_;
  std::unique_ptr<std::atomic<bool>[]> taken_;
};

// body(part, first, last) for the items [first, last) of each of ownedParts(n, most) parts.
template <typename Body>
void forOwnedParts(size_t n, size_t most, const Body& body) {
  OwnedPartClaims claims(n, most);
  if (claims.parts() == 0) return;
  tbb::parallel_for(size_t(0), claims.tasks(), [&](size_t) { claims.run(body); }, tbb::static_partitioner());
}

// A busy wait's pause (a hint to the core; nothing elsewhere).
inline void spinPause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

// forOwnedParts(n, most, first), then forOwnedParts(n, most, second), in one parallel region: a
// thread out of first's parts waits (spinning: the parts it waits for are running on another
// thread) until all are done, then takes second's. A parallel region of two ~3 µs tasks took
// 11.7 µs with the cores far apart and 6.9 µs close; the wait costs part of that again, so two
// regions made one (stitching, evaluation) took 1 % off the creased torus at 1e-3 in either
// placement. If `first` throws, second is skipped and the exception propagates. Neither body
// may start TBB work of its own: a thread stealing inside it could take this region's other task
// and wait there for the very part it is running.
template <typename First, typename Second>
void forOwnedPartsTwice(size_t n, size_t most, const First& first, const Second& second) {
  OwnedPartClaims firstClaims(n, most), secondClaims(n, most);
  if (firstClaims.parts() == 0) return;
  std::atomic<size_t> firstDone{0};
  std::atomic<bool> failed{false};
  // A part counts as done however it ends, so that no thread waits for a part that threw.
  auto countedFirst = [&](size_t part, size_t from, size_t to) {
    struct Count {
      std::atomic<size_t>& done;
      ~Count() { done.fetch_add(1, std::memory_order_release); }
    } count{firstDone};
    try {
      first(part, from, to);
    } catch (...) {
      failed.store(true, std::memory_order_relaxed);
      throw;
    }
  };
  tbb::parallel_for(
      size_t(0), firstClaims.tasks(),
      [&](size_t) {
        firstClaims.run(countedFirst);
        while (firstDone.load(std::memory_order_acquire) < firstClaims.parts()) {
          if (failed.load(std::memory_order_relaxed)) return;
          spinPause();
        }
        if (!failed.load(std::memory_order_relaxed)) secondClaims.run(second);
      },
      tbb::static_partitioner());
}

}  // namespace tessera
