#include "server/render/render_vulkan_backend.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <utility>

#include "gpu/vulkan/vulkan_error.h"
#include "gpu/vulkan/device_probe.h"

namespace tessera::server {
namespace {

using Clock = std::chrono::steady_clock;

// How often a frame waiting for the device checks whether its call was cancelled.
constexpr auto kCancelPoll = std::chrono::milliseconds(20);

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

std::string describeDevice(const gpu::DeviceInfo& info) {
  return fmt::format("{} ({}), {}, {}", info.name, info.driver, gpu::deviceKindName(info.kind),
                     info.meshShaders ? "mesh-shader path (VK_EXT_mesh_shader)"
                                      : "compute path (no VK_EXT_mesh_shader)");
}

// What a frame holds, measured on lavapipe (bench/MEMORY-RESULTS.md), rounded up: per pixel the
// colour, depth and crack-filling images, their readback and the returned buffers; per drawn
// triangle its share of the render patches (the geometry buffers are per batch, not per frame).
constexpr int64_t kFrameBytesPerPixel = 72;  // 67 measured in all at 4096 x 4096
constexpr int64_t kFrameBaseBytes = 16 << 20;
constexpr int64_t kDrawnBytesPerTriangle = 32;

// What the renderer may keep from a frame for the next one (its render targets, geometry and
// patch buffers): a 1920 x 1080 frame's targets (91 MB on lavapipe) stay for the viewer's next
// frame of that size; a larger frame's are freed as soon as it is read back. Kept, one
// 8192 x 8192 frame held ~2.9 GB until the next frame (issue 47, bench/MEMORY-RESULTS.md).
constexpr uint64_t kKeptFrameBytes = 128ull << 20;

// FrameEngine's request for a job: default background, light, material and geometry path.
// The camera in the frame of the mesh's positions (relative to its origin).
gpu::FrameRequest frameRequestFor(const FrameJob& job, const Vec3d& origin) {
  gpu::FrameRequest request;
  request.camera = job.camera;
  request.camera.eye = job.camera.eye - origin;
  request.camera.target = job.camera.target - origin;
  const FrameSettings& s = job.settings;
  request.accuracy = s.accuracy;
  request.eta = s.eta;
  if (s.maxTriangles > 0) request.maxTriangles = s.maxTriangles;
  request.render.crackFilling = s.crackFilling;
  request.render.readPatchIds = false;  // the service sends colour (and depth, for EXR) only
  return request;
}

// Frees what the renderer kept of a frame too large to keep (the device's lock is held).
void releaseLargeFrame(gpu::Renderer& renderer) {
  const uint64_t held = renderer.frameMemoryBytes();
  if (held <= kKeptFrameBytes) return;
  renderer.releaseFrameMemory();
  spdlog::debug("render: freed {:.0f} MiB of frame buffers", double(held) / (1 << 20));
}

}  // namespace

int64_t VulkanRenderBackend::frameBytes(int width, int height) const {
  return kFrameBaseBytes + kFrameBytesPerPixel * int64_t(width) * int64_t(height);
}

VulkanRenderBackend::VulkanRenderBackend(PatchSetCache& patches, gpu::DeviceSelection selection,
                                         bool probeDevice)
    : selection_(std::move(selection)), patches_(patches) {
  detail_ =
      "Vulkan renderer (paper §5-6: CPU planning, GPU tessellation and crack filling); "
      "device chosen at the first frame";
  if (!probeDevice) return;
  // The renderer (device, pipelines, buffers) waits for the first frame, so a server that never
  // renders pays little for it.
  Clock::time_point start = Clock::now();
  try {
    gpu::ProbedDevice probed = gpu::probeRenderDevice(selection_);
    std::string what =
        fmt::format("{} ({}), {}{}", probed.name, probed.driver, gpu::deviceKindName(probed.kind),
                    probed.meshShaderExtension ? ", VK_EXT_mesh_shader" : "");
    {
      std::lock_guard lock(info_);
      deviceName_ = probed.name;
      detail_ = fmt::format("Vulkan renderer on {}; created at the first frame", what);
    }
    spdlog::info("render device: {} (probed in {:.0f} ms)", what, millisecondsSince(start));
  } catch (const std::exception& error) {
    std::lock_guard lock(info_);
    failed_ = true;
    detail_ = fmt::format("no usable Vulkan device: {}", error.what());
    spdlog::warn("rendering unavailable: {}", detail_);
  }
}

VulkanRenderBackend::~VulkanRenderBackend() = default;

bool VulkanRenderBackend::available() const {
  std::lock_guard lock(info_);
  return !failed_;
}

std::string VulkanRenderBackend::detail() const {
  std::lock_guard lock(info_);
  return detail_;
}

std::string VulkanRenderBackend::device() const {
  std::lock_guard lock(info_);
  return deviceName_;
}

void VulkanRenderBackend::describe(const gpu::DeviceInfo& info, const char* when) {
  std::lock_guard lock(info_);
  if (!deviceName_.empty() && deviceName_ != info.name) {
    spdlog::warn(
        "the renderer runs on {}, not on {} as probed at start (GetServerInfo names the "
        "probed one)",
        info.name, deviceName_);
  }
  deviceName_ = info.name;
  detail_ = fmt::format("Vulkan renderer on {}; {}", describeDevice(info), when);
}

gpu::FrameEngine& VulkanRenderBackend::engineLocked() {
  if (engine_) return *engine_;
  if (!unavailable_.empty()) throw RenderUnavailable(unavailable_);
  Clock::time_point start = Clock::now();
  try {
    engine_.emplace(gpu::FrameEngine::create(selection_));
  } catch (const std::exception& error) {
    unavailable_ = fmt::format("no usable Vulkan device: {}", error.what());
    {
      std::lock_guard lock(info_);
      failed_ = true;
      detail_ = unavailable_;
    }
    spdlog::error("rendering unavailable: {}", unavailable_);
    throw RenderUnavailable(unavailable_);
  }
  gpu::DeviceInfo info = engine_->renderer().info();
  describe(info, "created");
  spdlog::info("render device created in {:.0f} ms: {}", millisecondsSince(start),
               describeDevice(info));
  return *engine_;
}

gpu::Frame VulkanRenderBackend::drawLocked(const gpu::PreparedFrame& prepared) {
  gpu::FrameEngine& engine = engineLocked();
  // Freed however the frame ends: a cancelled 8192 x 8192 frame holds as much as a finished one.
  // (A lost device has been dropped by then: nothing left to free.)
  struct Release {
    std::optional<gpu::FrameEngine>& engine;
    ~Release() {
      if (engine) releaseLargeFrame(engine->renderer());
    }
  } release{engine_};
  try {
    return engine.renderer().render(prepared.patches, prepared.camera, prepared.options);
  } catch (const gpu::VulkanError& error) {
    if (error.result() == VK_ERROR_DEVICE_LOST) {
      spdlog::error("render device lost ({}); the next frame creates a new one", error.what());
      engine_.reset();
    }
    throw;
  } catch (const gpu::RenderInputError& error) {
    // The camera was checked before: what is left is more than the device can take.
    throw RenderLimitExceeded(error.what());
  } catch (const gpu::RenderUnsupportedError& error) {
    throw RenderUnavailable(error.what());
  }
}

RenderedFrame VulkanRenderBackend::render(const ControlMesh& mesh, const FrameJob& job,
                                          const CancellationToken& cancel) {
  RenderedFrame out;
  Clock::time_point planStart = Clock::now();
  std::shared_ptr<const PatchSet> patches = patches_.get(mesh, job.meshSha256, cancel, job.memory);
  cancel.throwIfCancelled();
  gpu::FrameRequest request = frameRequestFor(job, mesh.origin);
  request.render.checkpoint = [&cancel] { cancel.throwIfCancelled(); };  // planning and each GPU stage
  if (job.memory) {
    request.beforeDrawing = [&job](int64_t triangles) {
      job.memory->reserve(kDrawnBytesPerTriangle * triangles,
                          "drawing " + std::to_string(triangles) + " triangles");
    };
  }
  gpu::PreparedFrame prepared = gpu::prepareFrame(*patches, request);
  out.times.planMs = millisecondsSince(planStart);
  cancel.throwIfCancelled();

  Clock::time_point waitStart = Clock::now();
  std::unique_lock lock(device_, std::defer_lock);
  while (!lock.try_lock_for(kCancelPoll)) cancel.throwIfCancelled();
  cancel.throwIfCancelled();
  out.device = engineLocked().renderer().info().name;  // the first frame creates the device
  out.times.waitMs = millisecondsSince(waitStart);
  Clock::time_point renderStart = Clock::now();
  gpu::Frame frame = drawLocked(prepared);
  lock.unlock();
  out.times.renderMs = millisecondsSince(renderStart);

  out.times.tessellationMs = frame.timings.tessellationMs;
  out.times.rasterShadingMs = frame.timings.rasterShadingMs;
  out.times.crackFillingMs = frame.timings.crackFillingMs;
  out.times.gpuTimestamps = frame.timings.fromTimestamps;
  const gpu::FrameStatistics& s = prepared.statistics;
  out.counts.triangles = int64_t(frame.trianglesGenerated);
  out.counts.pieces = s.pieces;
  out.counts.visiblePieces = s.visiblePieces;
  out.counts.renderPatches = s.renderPatches;
  out.counts.rings = s.rings;
  out.counts.averageRingDepth = s.averageRingDepth;
  out.counts.maxRingDepth = s.maxRingDepth;
  out.counts.guaranteedBound = s.guaranteedBound;
  out.width = frame.width;
  out.height = frame.height;
  out.rgba = std::move(frame.rgba);
  out.depth = std::move(frame.depth);
  return out;
}

}  // namespace tessera::server
