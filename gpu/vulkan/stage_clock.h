// Per-stage frame timings. The recording code calls enter(stage) at each stage boundary.
// On GPUs this writes a timestamp query (its value is when all earlier commands finished).
// On CPU implementations (lavapipe) timestamps are resolved when llvmpipe flushes its binned
// scene, after synchronous compute dispatches have already run, so they misattribute the
// compute stages; there, and on queues without timestamps, each stage becomes its own
// submission timed on the host instead.
#pragma once

#include <vulkan/vulkan.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <vector>

#include "gpu/vulkan/render_types.h"

namespace tessera::gpu {

class VulkanContext;

enum class Stage { kSetup, kTessellation, kRaster, kCrackFilling, kReadback, kCount };

class StageClock {
 public:
  StageClock(const VulkanContext& context, VkCommandBuffer cmd, VkFence fence);
  ~StageClock();
  StageClock(const StageClock&) = delete;
  StageClock& operator=(const StageClock&) = delete;

  bool usesTimestamps() const { return useTimestamps_; }

  // Starts recording a frame (stage kSetup); `maxStages` bounds the enter() calls. `checkpoint`
  // (may be null) runs after each submission has completed and may throw to abandon the frame.
  void begin(uint32_t maxStages, std::function<void()> checkpoint = {});
  void enter(Stage stage);
  // Ends recording, submits, waits for completion and fills the stage fields of `timings`.
  void finish(StageTimings& timings);

 private:
  void beginCommands();
  void submitAndWait();
  void ensurePool(uint32_t queries);

  VkDevice device_;
  VkQueue queue_;
  VkCommandBuffer cmd_;
  VkFence fence_;
  bool useTimestamps_;
  double nanosecondsPerTick_;
  uint64_t validMask_;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  uint32_t capacity_ = 0;
  std::vector<Stage> marks_;  // the stage that starts at each timestamp
  std::function<void()> checkpoint_;
  Stage current_ = Stage::kSetup;
  std::array<double, size_t(Stage::kCount)> hostMs_{};
  std::chrono::steady_clock::time_point sectionStart_;
  double submittedMs_ = 0.0;
};

}  // namespace tessera::gpu
