// SingleFlight (server/meshes/single_flight.h) in process, with builders the tests hold and
// release: calls for one key build once; a builder whose call gives up leaves the build to one
// of its waiters, which do not inherit its cancellation; a failure of the key itself reaches
// every waiter; a waiter whose own call is cancelled stops waiting at once; and a waiter counts
// for admission control as a job waiting for another.
//
// A waiter polls its cancellation token while it waits, and only then: the tests' tokens record
// that poll to know a call is waiting before they let the build go on.
#include "server/meshes/single_flight.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <future>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "server/calls/admission_control.h"
#include "server/calls/status_error.h"
#include "tests/server/gate.h"

namespace tessera::server {
namespace {

using namespace std::chrono_literals;

// The failure of a key: every build of it would throw it.
struct BadKey : std::runtime_error {
  using std::runtime_error::runtime_error;
};

using Flights = SingleFlight<std::string, std::string, BadKey>;
using ValuePtr = Flights::ValuePtr;

using test::Gate;

// Where the builds store their values (the cache a real SingleFlight sits in front of).
class Store {
 public:
  ValuePtr find(const std::string& key) {
    std::lock_guard lock(mutex_);
    auto it = values_.find(key);
    return it == values_.end() ? nullptr : it->second;
  }
  ValuePtr put(const std::string& key, std::string value) {
    auto stored = std::make_shared<const std::string>(std::move(value));
    std::lock_guard lock(mutex_);
    values_[key] = stored;
    return stored;
  }

 private:
  std::mutex mutex_;
  std::map<std::string, ValuePtr> values_;
};

// A token that never fires and signals `waiting` the first time it is polled.
CancellationToken markingToken(Gate& waiting) {
  auto polled = std::make_shared<std::atomic<bool>>(false);
  return CancellationToken([&waiting, polled] {
    if (!polled->exchange(true)) waiting.open();
    return false;
  });
}

class SingleFlightTest : public ::testing::Test {
 protected:
  // get() with the store as its cache and `build` counted.
  template <typename Build>
  ValuePtr get(const CancellationToken& cancel, Build build, MemoryReservation* memory = nullptr) {
    return flights_.get(
        "k", cancel, memory, [&] { return store_.find("k"); },
        [&] {
          builds_.fetch_add(1);
          return build();
        });
  }

  Flights flights_;
  Store store_;
  std::atomic<int> builds_{0};
};

TEST_F(SingleFlightTest, ConcurrentCallsForOneKeyBuildOnce) {
  constexpr int kWaiters = 7;
  Gate started, all[kWaiters];
  auto builder = std::async(std::launch::async, [&] {
    return get({}, [&] {
      started.open();
      for (Gate& waiting : all) EXPECT_TRUE(waiting.wait());
      return store_.put("k", "built");
    });
  });
  ASSERT_TRUE(started.wait());
  std::vector<std::future<ValuePtr>> waiters;
  for (Gate& waiting : all) {
    waiters.push_back(std::async(std::launch::async, [&, token = markingToken(waiting)] {
      return get(token, [&] { return store_.put("k", "built again"); });
    }));
  }
  const ValuePtr built = builder.get();
  for (auto& waiter : waiters) EXPECT_EQ(waiter.get(), built);
  EXPECT_EQ(builds_.load(), 1);
  EXPECT_EQ(*built, "built");
  EXPECT_EQ(flights_.inFlight(), 0u);

  // Later calls find it where the build stored it.
  EXPECT_EQ(get({}, [&] { return store_.put("k", "rebuilt"); }), built);
  EXPECT_EQ(builds_.load(), 1);
}

TEST_F(SingleFlightTest, ACancelledBuilderLeavesTheBuildToAWaiterWhichIsNotCancelled) {
  Gate started, waiting;
  auto builder = std::async(std::launch::async, [&] {
    return get({}, [&]() -> ValuePtr {
      started.open();
      EXPECT_TRUE(waiting.wait());
      throw OperationCancelled();  // the builder's own call ended
    });
  });
  ASSERT_TRUE(started.wait());
  auto waiter = std::async(std::launch::async, [&] {
    return get(markingToken(waiting), [&] { return store_.put("k", "built by the waiter"); });
  });
  EXPECT_THROW(builder.get(), OperationCancelled);
  const ValuePtr value = waiter.get();
  ASSERT_TRUE(value);
  EXPECT_EQ(*value, "built by the waiter");
  EXPECT_EQ(builds_.load(), 2);
}

TEST_F(SingleFlightTest, AnyOtherFailureOfTheBuildersCallIsItsOwnToo) {
  // A memory reservation refused, or anything unexpected: the waiter builds.
  Gate started, waiting;
  auto builder = std::async(std::launch::async, [&] {
    return get({}, [&]() -> ValuePtr {
      started.open();
      EXPECT_TRUE(waiting.wait());
      throw StatusError(grpc::StatusCode::RESOURCE_EXHAUSTED, "the builder's memory");
    });
  });
  ASSERT_TRUE(started.wait());
  auto waiter = std::async(std::launch::async, [&] {
    return get(markingToken(waiting), [&] { return store_.put("k", "built by the waiter"); });
  });
  EXPECT_THROW(builder.get(), StatusError);
  ASSERT_TRUE(waiter.get());
  EXPECT_EQ(builds_.load(), 2);
}

TEST_F(SingleFlightTest, AFailureOfTheKeyReachesEveryWaiterWithoutAnotherBuild) {
  Gate started, waiting;
  auto builder = std::async(std::launch::async, [&] {
    return get({}, [&]() -> ValuePtr {
      started.open();
      EXPECT_TRUE(waiting.wait());
      throw BadKey("unsupported input");
    });
  });
  ASSERT_TRUE(started.wait());
  auto waiter = std::async(std::launch::async, [&] {
    return get(markingToken(waiting), [&] { return store_.put("k", "never"); });
  });
  EXPECT_THROW(builder.get(), BadKey);
  try {
    waiter.get();
    ADD_FAILURE() << "the waiter got a value";
  } catch (const BadKey& error) {
    EXPECT_STREQ(error.what(), "unsupported input");
  }
  EXPECT_EQ(builds_.load(), 1);
  // Failures are not remembered: the next call builds again.
  EXPECT_TRUE(get({}, [&] { return store_.put("k", "fixed"); }));
  EXPECT_EQ(builds_.load(), 2);
}

TEST_F(SingleFlightTest, ACancelledWaiterStopsWaitingAtOnceAndTheBuildGoesOn) {
  Gate started, release, waiting;
  auto builder = std::async(std::launch::async, [&] {
    return get({}, [&] {
      started.open();
      EXPECT_TRUE(release.wait());
      return store_.put("k", "built");
    });
  });
  ASSERT_TRUE(started.wait());
  std::atomic<bool> cancelled{false};
  CancellationToken token([&] {
    waiting.open();
    return cancelled.load();
  });
  auto waiter = std::async(std::launch::async,
                           [&] { return get(token, [&] { return store_.put("k", "no"); }); });
  ASSERT_TRUE(waiting.wait());
  const auto cancelledAt = std::chrono::steady_clock::now();
  cancelled = true;
  ASSERT_EQ(waiter.wait_for(2s), std::future_status::ready) << "the waiter is still waiting";
  EXPECT_LT(std::chrono::steady_clock::now() - cancelledAt, 500ms);
  EXPECT_THROW(waiter.get(), OperationCancelled);

  EXPECT_EQ(builder.wait_for(100ms), std::future_status::timeout)
      << "the build stopped with the waiter";
  release.open();
  ASSERT_TRUE(builder.get());
  EXPECT_EQ(builds_.load(), 1);
}

TEST_F(SingleFlightTest, AWaiterCountsAsAJobWaitingForAnother) {
  // The builder needs memory the waiter holds, and the waiter waits for the builder: the builder
  // is refused with a retry hint instead of both waiting until their deadlines.
  constexpr int64_t kMiB = 1 << 20;
  AdmissionControl admission(2, 8, 100 * kMiB);
  CancellationToken never;
  AdmissionControl::Slot builderJob = admission.acquire(never, {}, 10 * kMiB);
  AdmissionControl::Slot waiterJob = admission.acquire(never, {}, 60 * kMiB);  // a frame's pixels
  Gate started, waiting;
  auto builder = std::async(std::launch::async, [&] {
    return get(
        never,
        [&] {
          started.open();
          EXPECT_TRUE(waiting.wait());
          builderJob.reserve(50 * kMiB, "preprocessing the mesh");
          return store_.put("k", "built");
        },
        &builderJob);
  });
  ASSERT_TRUE(started.wait());
  auto waiter = std::async(std::launch::async, [&] {
    return get(
        markingToken(waiting), [&] { return store_.put("k", "built by the waiter"); }, &waiterJob);
  });
  ASSERT_EQ(builder.wait_for(5s), std::future_status::ready)
      << "the builder waits for memory the waiter holds";
  try {
    builder.get();
    ADD_FAILURE() << "the builder's reservation was granted";
  } catch (const StatusError& error) {
    EXPECT_EQ(error.code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_GT(error.retryAfterMs().value_or(0), 0) << error.what();
  }
  // The waiter did not inherit the refusal: it built.
  ASSERT_TRUE(waiter.get());
  EXPECT_EQ(builds_.load(), 2);
  EXPECT_EQ(builderJob.reserved(), 10 * kMiB);
}

}  // namespace
}  // namespace tessera::server
