// Parts owned by thread slots (core/base/parallel_chunks.h) and scratch that goes back to the slot that
// gave it (core/base/scratch_pool.h).
#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "core/base/parallel_chunks.h"
#include "core/base/scratch_pool.h"

namespace tessera {
namespace {

struct Visit {
  size_t part, first, last;
};

// Every item once, in the parts ownedParts names: contiguous, in order, at most `most` items
// each and at least four a thread where there are items enough.
void expectEveryItemOnce(int threads, size_t n, size_t most) {
  tbb::task_arena arena(threads);
  arena.execute([&] {
    std::vector<std::atomic<int>> seen(n);
    std::mutex mutex;
    std::vector<Visit> visits;
    forOwnedParts(n, most, [&](size_t part, size_t first, size_t last) {
      for (size_t i = first; i < last; ++i) seen[i].fetch_add(1);
      const std::lock_guard<std::mutex> lock(mutex);
      visits.push_back({part, first, last});
    });
    for (size_t i = 0; i < n; ++i) EXPECT_EQ(seen[i].load(), 1) << "item " << i << " of " << n;
    const size_t parts = ownedParts(n, most);
    ASSERT_EQ(visits.size(), parts);
    EXPECT_EQ(parts, std::min(n, std::max<size_t>(4 * size_t(threads), (n + most - 1) / most)));
    std::vector<Visit> byPart(parts);
    for (const Visit& v : visits) byPart.at(v.part) = v;
    for (size_t p = 0; p < parts; ++p) {
      EXPECT_EQ(byPart[p].first, p == 0 ? 0 : byPart[p - 1].last);
      EXPECT_LE(byPart[p].last - byPart[p].first, std::max(most, (n + 4 * threads - 1) / (4 * threads)));
    }
    if (parts > 0) {
      EXPECT_EQ(byPart.back().last, n);
    }
  });
}

TEST(OwnedParts, EveryItemOnceInContiguousParts) {
  for (int threads : {1, 2, 4}) {
    for (size_t n : {size_t(0), size_t(1), size_t(3), size_t(32), size_t(1000), size_t(5000)}) {
      SCOPED_TRACE(testing::Message() << threads << " threads, " << n << " items");
      expectEveryItemOnce(threads, n, 16);
    }
  }
}

// With two threads, each slot runs its own parts before any other: across many calls the part a
// slot runs first is always one of its own (the other thread takes a late slot's parts only once
// it has run all of its own, so a slot that finds all of its own taken finds nothing left).
TEST(OwnedParts, EachSlotRunsItsOwnPartsFirst) {
  tbb::task_arena arena(2);
  arena.execute([&] {
    for (int call = 0; call < 200; ++call) {
      std::mutex mutex;
      std::vector<std::vector<size_t>> bySlot(2);
      forOwnedParts(32, 16, [&](size_t part, size_t, size_t) {
        const int slot = tbb::this_task_arena::current_thread_index();
        const std::lock_guard<std::mutex> lock(mutex);
        bySlot.at(size_t(slot)).push_back(part);
      });
      for (size_t slot = 0; slot < 2; ++slot) {
        if (bySlot[slot].empty()) continue;
        const size_t first = bySlot[slot].front();
        EXPECT_TRUE(first >= slot * 4 && first < (slot + 1) * 4) << "slot " << slot << " began with part " << first;
      }
    }
  });
}

// Both steps see every item once, and no item of the second before every item of the first.
TEST(OwnedParts, TwiceRunsTheSecondStepAfterAllOfTheFirst) {
  for (int threads : {1, 2, 4}) {
    tbb::task_arena arena(threads);
    arena.execute([&] {
      for (size_t n : {size_t(1), size_t(7), size_t(32), size_t(3000)}) {
        std::vector<std::atomic<int>> first(n), second(n);
        std::atomic<size_t> firstDone{0};
        std::atomic<bool> early{false};
        forOwnedPartsTwice(
            n, 16,
            [&](size_t, size_t from, size_t to) {
              for (size_t i = from; i < to; ++i) first[i].fetch_add(1);
              firstDone.fetch_add(to - from);
            },
            [&](size_t, size_t from, size_t to) {
              if (firstDone.load() != n) early = true;
              for (size_t i = from; i < to; ++i) second[i].fetch_add(1);
            });
        EXPECT_FALSE(early.load()) << threads << " threads, " << n << " items";
        for (size_t i = 0; i < n; ++i) {
          EXPECT_EQ(first[i].load(), 1) << "item " << i;
          EXPECT_EQ(second[i].load(), 1) << "item " << i;
        }
      }
    });
  }
}

// A first step that throws (a cancelled request's checkpoint) ends the call: no thread waits
// for it forever, the second step does not run, and the exception reaches the caller.
TEST(OwnedParts, TwiceStopsWhereTheFirstStepThrows) {
  tbb::task_arena arena(2);
  arena.execute([&] {
    std::atomic<int> secondRan{0};
    EXPECT_THROW(forOwnedPartsTwice(
                     64, 16,
                     [&](size_t part, size_t, size_t) {
                       if (part == 5) throw std::runtime_error("cancelled");
                     },
                     [&](size_t, size_t, size_t) { secondRan.fetch_add(1); }),
                 std::runtime_error);
    EXPECT_EQ(secondRan.load(), 0);
  });
}

struct Room {
  std::vector<int> data;
  size_t clearKeepingRoom() {
    data.clear();
    return data.capacity() * sizeof(int);
  }
};

TEST(ScratchPool, SlotTakesBackWhatItGave) {
  ScratchPool<Room> pool(1 << 20);
  auto a = std::make_unique<Room>(), b = std::make_unique<Room>();
  Room* const fromSlotZero = a.get();
  Room* const fromSlotOne = b.get();
  pool.give(std::move(a), 0);
  pool.give(std::move(b), 1);
  EXPECT_EQ(pool.take(0).get(), fromSlotZero);
  EXPECT_EQ(pool.take(1).get(), fromSlotOne);
}

TEST(ScratchPool, AnotherSlotsRoomRatherThanNone) {
  ScratchPool<Room> pool(1 << 20);
  auto a = std::make_unique<Room>();
  a->data.reserve(100);
  Room* const kept = a.get();
  pool.give(std::move(a), 3);
  const std::unique_ptr<Room> taken = pool.take(0);
  EXPECT_EQ(taken.get(), kept);
  EXPECT_GE(taken->data.capacity(), 100u);
  EXPECT_TRUE(taken->data.empty());
}

TEST(ScratchPool, RoomOverTheCapIsFreed) {
  ScratchPool<Room> pool(16);
  auto a = std::make_unique<Room>();
  a->data.reserve(100);
  pool.give(std::move(a), 0);
  EXPECT_EQ(pool.take(0)->data.capacity(), 0u);
}

}  // namespace
}  // namespace tessera
