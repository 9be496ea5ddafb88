#include "gpu/vulkan/stage_clock.h"

#include <utility>

#include "gpu/vulkan/vulkan_context.h"
#include "gpu/vulkan/vulkan_error.h"

namespace tessera::gpu {
namespace {

using Clock = std::chrono::steady_clock;

// A frame that has not finished after this long is reported, not waited on forever.
constexpr uint64_t kFrameTimeoutNs = 300ull * 1000 * 1000 * 1000;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

uint64_t timestampMask(const VulkanContext& context) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(context.physicalDevice(), &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(context.physicalDevice(), &count, families.data());
  uint32_t bits = families[context.queueFamily()].timestampValidBits;
  return bits >= 64 ? ~0ull : ((1ull << bits) - 1);
}

void addStage(StageTimings& t, Stage stage, double ms) {
  switch (stage) {
    case Stage::kTessellation:
      t.tessellationMs += ms;
      break;
    case Stage::kRaster:
      t.rasterShadingMs += ms;
      break;
    case Stage::kCrackFilling:
      t.crackFillingMs += ms;
      break;
    default:
      break;  // setup and readback count only towards the totals
  }
}

}  // namespace

StageClock::StageClock(const VulkanContext& context, VkCommandBuffer cmd, VkFence fence)
    : device_(context.device()),
      queue_(context.queue()),
      cmd_(cmd),
      fence_(fence),
      useTimestamps_(context.info().timestamps && context.info().kind != DeviceKind::kCpu),
      nanosecondsPerTick_(context.limits().timestampPeriod),
      validMask_(timestampMask(context)) {}

StageClock::~StageClock() {
  if (pool_) vkDestroyQueryPool(device_, pool_, nullptr);
}

void StageClock::ensurePool(uint32_t queries) {
  if (queries <= capacity_) return;
  if (pool_) vkDestroyQueryPool(device_, pool_, nullptr);
  pool_ = VK_NULL_HANDLE;
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = queries;
  vkCheck(vkCreateQueryPool(device_, &info, nullptr, &pool_), "vkCreateQueryPool");
  capacity_ = queries;
}

void StageClock::beginCommands() {
  vkCheck(vkResetCommandBuffer(cmd_, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vkCheck(vkBeginCommandBuffer(cmd_, &begin), "vkBeginCommandBuffer");
}

void StageClock::submitAndWait() {
  vkCheck(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");
  vkCheck(vkResetFences(device_, 1, &fence_), "vkResetFences");
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd_;
  vkCheck(vkQueueSubmit(queue_, 1, &submit, fence_), "vkQueueSubmit");
  VkResult waited = vkWaitForFences(device_, 1, &fence_, VK_TRUE, kFrameTimeoutNs);
  if (waited == VK_TIMEOUT) throw VulkanError("vkWaitForFences (frame timeout)", waited);
  vkCheck(waited, "vkWaitForFences");
}

void StageClock::begin(uint32_t maxStages, std::function<void()> checkpoint) {
  checkpoint_ = std::move(checkpoint);
  marks_.clear();
  hostMs_.fill(0.0);
  submittedMs_ = 0.0;
  current_ = Stage::kSetup;
  beginCommands();
  sectionStart_ = Clock::now();
  if (!useTimestamps_) return;
  ensurePool(maxStages + 2);
  vkCmdResetQueryPool(cmd_, pool_, 0, capacity_);
  enter(Stage::kSetup);
}

void StageClock::enter(Stage stage) {
  if (useTimestamps_) {
    if (marks_.size() >= capacity_) return;  // more stages than planned: merge into the last
    vkCmdWriteTimestamp2(cmd_, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_,
                         static_cast<uint32_t>(marks_.size()));
    marks_.push_back(stage);
    return;
  }
  // Host mode: everything recorded so far is the current stage's work.
  Clock::time_point start = Clock::now();
  submitAndWait();
  hostMs_[size_t(current_)] += millisecondsSince(start);
  submittedMs_ += millisecondsSince(start);
  // Nothing is pending: a throw here leaves the command buffer for the next begin() to reset.
  if (checkpoint_) checkpoint_();
  current_ = stage;
  beginCommands();
}

void StageClock::finish(StageTimings& timings) {
  timings.fromTimestamps = useTimestamps_;
  if (useTimestamps_) enter(Stage::kReadback);  // closes the last stage
  Clock::time_point start = Clock::now();
  submitAndWait();
  submittedMs_ += millisecondsSince(start);
  timings.gpuTotalMs = submittedMs_;
  if (!useTimestamps_) {
    hostMs_[size_t(current_)] += millisecondsSince(start);
    for (size_t s = 0; s < hostMs_.size(); ++s) addStage(timings, Stage(s), hostMs_[s]);
    return;
  }
  std::vector<uint64_t> ticks(marks_.size());
  vkCheck(vkGetQueryPoolResults(device_, pool_, 0, static_cast<uint32_t>(ticks.size()),
                                ticks.size() * sizeof(uint64_t), ticks.data(), sizeof(uint64_t),
                                VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
          "vkGetQueryPoolResults");
  for (size_t i = 0; i + 1 < ticks.size(); ++i) {
    double ms = double((ticks[i + 1] - ticks[i]) & validMask_) * nanosecondsPerTick_ * 1e-6;
    addStage(timings, marks_[i], ms);
  }
}

}  // namespace tessera::gpu
