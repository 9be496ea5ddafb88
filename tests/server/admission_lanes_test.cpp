// AdmissionControl's two lanes, in process: a light job is admitted while every main slot is
// held, light jobs queue in their own lane (first come, first served there), and a server without
// a light lane queues them behind the main jobs as before. Memory stays one budget for both.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <optional>

#include "server/calls/admission_control.h"
#include "server/calls/status_error.h"

namespace tessera::server {
namespace {

using namespace std::chrono_literals;
constexpr int64_t kMiB = 1 << 20;

// A job that tries for a slot on another thread; admitted once it has one. Gives up (its own
// cancellation) when the test ends, so that no thread waits on past it.
class Attempt {
 public:
  Attempt(AdmissionControl& admission, AdmissionLane lane, int64_t bytes = 0)
      : cancel_([this] { return stop_.load(); }),
        slot_(std::async(std::launch::async, [this, &admission, lane, bytes] {
          return std::make_shared<AdmissionControl::Slot>(admission.acquire(cancel_, {}, bytes, "the job", lane));
        })) {}
  ~Attempt() {
    stop_ = true;
    if (slot_.valid()) slot_.wait();
  }
  bool admittedWithin(std::chrono::milliseconds wait) { return slot_.wait_for(wait) == std::future_status::ready; }

 private:
  std::atomic<bool> stop_{false};
  CancellationToken cancel_;
  std::future<std::shared_ptr<AdmissionControl::Slot>> slot_;
};

TEST(AdmissionLanes, ALightJobIsAdmittedWhileEveryMainSlotIsHeld) {
  AdmissionControl admission(1, 8);
  CancellationToken never;
  AdmissionControl::Slot longJob = admission.acquire(never);
  Attempt queuedMain(admission, AdmissionLane::kMain);
  EXPECT_FALSE(queuedMain.admittedWithin(100ms)) << "the main lane's only slot is held";
  Attempt light(admission, AdmissionLane::kLight);
  EXPECT_TRUE(light.admittedWithin(2s)) << "a light job must not wait behind the main lane";
  EXPECT_EQ(admission.running(AdmissionLane::kLight), 1);
  EXPECT_EQ(admission.queued(AdmissionLane::kMain), 1);
  EXPECT_EQ(admission.running(), 2);
}

TEST(AdmissionLanes, LightJobsQueueInTheirOwnLaneFirstComeFirstServed) {
  AdmissionControl admission(1, 8, AdmissionControl::kUnlimited, "", 1);
  CancellationToken never;
  std::optional<AdmissionControl::Slot> first(admission.acquire(never, {}, 0, "the job", AdmissionLane::kLight));
  Attempt second(admission, AdmissionLane::kLight);
  EXPECT_FALSE(second.admittedWithin(100ms)) << "the light lane has one slot";
  EXPECT_EQ(admission.queued(AdmissionLane::kLight), 1);
  // The main lane is not the light lane's overflow, nor the other way round.
  Attempt main(admission, AdmissionLane::kMain);
  EXPECT_TRUE(main.admittedWithin(2s));
  first.reset();
  EXPECT_TRUE(second.admittedWithin(2s));
}

TEST(AdmissionLanes, WithoutALightLaneLightJobsWaitBehindTheMainOnes) {
  AdmissionControl admission(1, 8, AdmissionControl::kUnlimited, "", -1);
  CancellationToken never;
  std::optional<AdmissionControl::Slot> longJob(admission.acquire(never));
  Attempt light(admission, AdmissionLane::kLight);
  EXPECT_FALSE(light.admittedWithin(200ms));
  longJob.reset();
  EXPECT_TRUE(light.admittedWithin(2s));
}

TEST(AdmissionLanes, BothLanesShareOneMemoryBudget) {
  AdmissionControl admission(1, 8, 100 * kMiB);
  CancellationToken never;
  std::optional<AdmissionControl::Slot> big(admission.acquire(never, {}, 80 * kMiB));
  Attempt light(admission, AdmissionLane::kLight, 30 * kMiB);
  EXPECT_FALSE(light.admittedWithin(200ms)) << "30 MiB beside 80 MiB is over the 100 MiB budget";
  big.reset();
  EXPECT_TRUE(light.admittedWithin(2s));
  EXPECT_EQ(admission.memoryReserved(), 30 * kMiB);
}

TEST(AdmissionLanes, AFullLightQueueIsRefusedWithARetryHint) {
  AdmissionControl admission(1, 1, AdmissionControl::kUnlimited, "", 1);
  CancellationToken never;
  AdmissionControl::Slot running = admission.acquire(never, {}, 0, "the job", AdmissionLane::kLight);
  Attempt waiting(admission, AdmissionLane::kLight);
  ASSERT_FALSE(waiting.admittedWithin(100ms));
  try {
    admission.acquire(never, {}, 0, "the job", AdmissionLane::kLight);
    FAIL() << "the light lane's queue is full";
  } catch (const StatusError& error) {
    EXPECT_EQ(error.code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_TRUE(error.retryAfterMs().has_value());
    EXPECT_NE(std::string(error.what()).find("light lane"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace tessera::server
