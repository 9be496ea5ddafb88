// The render backend of builds with the Vulkan renderer: gpu::FrameEngine's two halves, with
// the server's concurrency around them. Planning (core/, CPU) runs in the calling thread, as
// many at once as admission control lets in; the device has one queue, so drawing is serialized
// behind a mutex that waiters poll their cancellation on. The renderer is created at the first
// frame (shader pipelines, buffers), on the device DeviceSelection picks (TESSERA_VK_DEVICE);
// a device that cannot be created makes every later frame RenderUnavailable with the reason,
// and a lost device is dropped so that the next frame creates a new one.
//
// Patch sets come from the server's one PatchSetCache (patch_set_cache.h, keyed by content),
// which the tessellation engines share.
#pragma once

#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "core/rings/patch_set.h"
#include "gpu/render_engine/frame_engine.h"
#include "gpu/vulkan/device_selection.h"
#include "server/meshes/patch_set_cache.h"
#include "server/render/render_backend.h"

namespace tessera::server {

class VulkanRenderBackend final : public RenderBackend {
 public:
  VulkanRenderBackend(PatchSetCache& patches, gpu::DeviceSelection selection, bool probeDevice);
  ~VulkanRenderBackend() override;

  std::string name() const override { return "vulkan"; }
  bool available() const override;
  std::string detail() const override;
  std::string device() const override;
  int64_t frameBytes(int width, int height) const override;

  RenderedFrame render(const ControlMesh& mesh, const FrameJob& job,
                       const CancellationToken& cancel) override;

 private:
  // device_ must be held.
  gpu::FrameEngine& engineLocked();
  gpu::Frame drawLocked(const gpu::PreparedFrame& prepared);
  void describe(const gpu::DeviceInfo& info, const char* when);

  const gpu::DeviceSelection selection_;
  PatchSetCache& patches_;

  std::timed_mutex device_;                 // one frame at a time on the device's one queue
  std::optional<gpu::FrameEngine> engine_;  // guarded by device_
  std::string unavailable_;                 // guarded by device_ and info_: why no device

  mutable std::mutex info_;
  std::string deviceName_;  // guarded by info_
  std::string detail_;      // guarded by info_
  bool failed_ = false;     // guarded by info_
};

}  // namespace tessera::server
