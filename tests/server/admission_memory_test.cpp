// AdmissionControl's memory budget, in process: jobs are admitted by bytes as well as by count,
// reservations that could never fit are refused at once naming the estimate and the budget, a
// job that fits once another finishes waits for it, and two jobs never wait on each other (nor
// on one that waits for their work).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <optional>
#include <future>
#include <thread>

#include "server/calls/admission_control.h"
#include "server/calls/status_error.h"

namespace tessera::server {
namespace {

constexpr int64_t kMiB = 1 << 20;

grpc::StatusCode codeOf(const std::function<void()>& call, std::string* message = nullptr, int64_t* retry = nullptr) {
  try {
    call();
  } catch (const StatusError& error) {
    if (message) *message = error.what();
    if (retry) *retry = error.retryAfterMs().value_or(-1);
    return error.code();
  }
  return grpc::StatusCode::OK;
}

TEST(AdmissionMemory, AJobOverTheWholeBudgetIsRefusedAtOnceNamingEstimateAndBudget) {
  AdmissionControl admission(2, 8, 100 * kMiB, "--memory-budget test");
  CancellationToken cancel;
  std::string message;
  int64_t retry = -1;
  EXPECT_EQ(codeOf([&] { admission.acquire(cancel, {}, 300 * kMiB, "a 9000 x 9000 frame"); }, &message, &retry),
            grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(message.find("a 9000 x 9000 frame needs about 300 MiB"), std::string::npos) << message;
  EXPECT_NE(message.find("budget for jobs of 100 MiB (--memory-budget test)"), std::string::npos) << message;
  EXPECT_LE(retry, 0) << "retrying cannot help";
  EXPECT_EQ(admission.memoryReserved(), 0);
}

TEST(AdmissionMemory, ReservationsAddUpAndComeBackWhenTheJobEnds) {
  AdmissionControl admission(2, 8, 100 * kMiB);
  CancellationToken cancel;
  {
    AdmissionControl::Slot slot = admission.acquire(cancel, {}, 10 * kMiB);
    slot.reserve(30 * kMiB, "the output");
    EXPECT_EQ(admission.memoryReserved(), 40 * kMiB);
    slot.release(25 * kMiB);
    EXPECT_EQ(slot.reserved(), 15 * kMiB);
    std::string message;
    EXPECT_EQ(codeOf([&] { slot.reserve(90 * kMiB, "the output (9 triangles)"); }, &message),
              grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_NE(message.find("with the 15 MiB the job already holds"), std::string::npos) << message;
    EXPECT_EQ(admission.memoryReserved(), 15 * kMiB);
  }
  EXPECT_EQ(admission.memoryReserved(), 0);
}

TEST(AdmissionMemory, AJobThatFitsOnceAnotherEndsWaitsForIt) {
  AdmissionControl admission(2, 8, 100 * kMiB);
  CancellationToken cancel;
  std::optional<AdmissionControl::Slot> first(admission.acquire(cancel, {}, 70 * kMiB));
  bool queued = false;
  auto second = std::async(std::launch::async, [&] {
    AdmissionControl::Slot slot = admission.acquire(cancel, [&](int) { queued = true; }, 50 * kMiB);
    return slot.reserved();
  });
  EXPECT_EQ(second.wait_for(std::chrono::milliseconds(200)), std::future_status::timeout);
  EXPECT_TRUE(queued);
  first.reset();
  EXPECT_EQ(second.get(), 50 * kMiB);
}

TEST(AdmissionMemory, AGrowingJobWaitsForARunningOneButNotForAnotherGrowingOne) {
  AdmissionControl admission(3, 8, 100 * kMiB);
  CancellationToken cancel;
  std::optional<AdmissionControl::Slot> other(admission.acquire(cancel, {}, 60 * kMiB));
  AdmissionControl::Slot growing = admission.acquire(cancel, {}, 10 * kMiB);
  auto grow = std::async(std::launch::async, [&] { growing.reserve(50 * kMiB, "the output"); });
  EXPECT_EQ(grow.wait_for(std::chrono::milliseconds(200)), std::future_status::timeout);
  // A third job cannot start while one waits to grow, though its bytes would fit.
  auto third = std::async(std::launch::async, [&] { return admission.acquire(cancel, {}, 1 * kMiB).reserved(); });
  EXPECT_EQ(third.wait_for(std::chrono::milliseconds(100)), std::future_status::timeout);
  other.reset();
  grow.get();
  EXPECT_EQ(growing.reserved(), 60 * kMiB);
  EXPECT_EQ(third.get(), 1 * kMiB);

  // Two running jobs that both need more than is left: the first waits for the second, which
  // could give memory back; the second then has no one left to wait for (the first is waiting
  // itself) and is refused with a retry hint instead of both waiting for ever.
  std::optional<AdmissionControl::Slot> second(admission.acquire(cancel, {}, 30 * kMiB));
  auto first = std::async(std::launch::async, [&] { growing.reserve(30 * kMiB, "the output (3 triangles)"); });
  EXPECT_EQ(first.wait_for(std::chrono::milliseconds(100)), std::future_status::timeout);
  std::string message;
  int64_t retry = 0;
  EXPECT_EQ(codeOf([&] { second->reserve(30 * kMiB, "the output (4 triangles)"); }, &message, &retry),
            grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_GT(retry, 0) << message;
  EXPECT_NE(message.find("the output (4 triangles) needs about 30 MiB of memory and other jobs hold 60 MiB"),
            std::string::npos) << message;
  second.reset();  // the refused call ends and gives its memory back
  first.get();
  EXPECT_EQ(admission.memoryReserved(), 90 * kMiB);
}

TEST(AdmissionMemory, AJobWaitingForAnothersWorkCannotGiveMemoryBack) {
  // The other job holds memory but waits for this one's work (the patch set this one builds):
  // waiting for it would wait for ever, so the reservation is refused with a retry hint.
  AdmissionControl admission(2, 8, 100 * kMiB);
  CancellationToken cancel;
  AdmissionControl::Slot building = admission.acquire(cancel, {}, 10 * kMiB);
  AdmissionControl::Slot other = admission.acquire(cancel, {}, 60 * kMiB);
  std::string message;
  int64_t retry = 0;
  {
    MemoryReservation::WaitingForAnotherJob waiting(&other);
    EXPECT_EQ(codeOf([&] { building.reserve(50 * kMiB, "preprocessing the mesh"); }, &message, &retry),
              grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_GT(retry, 0) << message;
  }
  // Once it waits no more it can finish and give its memory back: the reservation waits for it.
  auto grow = std::async(std::launch::async, [&] { building.reserve(50 * kMiB, "preprocessing the mesh"); });
  EXPECT_EQ(grow.wait_for(std::chrono::milliseconds(100)), std::future_status::timeout);
  other.release(60 * kMiB);
  grow.get();
  EXPECT_EQ(building.reserved(), 60 * kMiB);
}

TEST(AdmissionMemory, AWaitingReservationEndsWhenTheJobIsCancelled) {
  AdmissionControl admission(2, 8, 100 * kMiB);
  CancellationToken cancel;
  std::atomic<bool> stop{false};
  CancellationToken cancelGrower([&] { return stop.load(); });
  AdmissionControl::Slot other = admission.acquire(cancel, {}, 80 * kMiB);
  AdmissionControl::Slot growing = admission.acquire(cancelGrower, {}, 10 * kMiB);
  auto grow = std::async(std::launch::async, [&] {
    try {
      growing.reserve(50 * kMiB, "the output");
    } catch (const OperationCancelled&) {
      return true;
    }
    return false;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  stop = true;
  EXPECT_TRUE(grow.get());
  EXPECT_EQ(admission.memoryReserved(), 90 * kMiB);
}

}  // namespace
}  // namespace tessera::server
