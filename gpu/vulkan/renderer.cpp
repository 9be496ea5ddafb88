#include "gpu/vulkan/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include "gpu/vulkan/camera_math.h"
#include "gpu/vulkan/compute_path.h"
#include "gpu/vulkan/crack_fill_pass.h"
#include "gpu/vulkan/frame_uniforms.h"
#include "gpu/vulkan/gpu_memory.h"
#include "gpu/vulkan/mesh_path.h"
#include "gpu/vulkan/patch_batches.h"
#include "gpu/vulkan/render_targets.h"
#include "gpu/vulkan/stage_clock.h"
#include "gpu/vulkan/vulkan_context.h"
#include "gpu/vulkan/vulkan_error.h"

namespace tessera::gpu {
namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

void validateOptions(const RenderOptions& options) {
  for (float c : options.background) {
    if (!std::isfinite(c) || c < 0.0f || c > 1.0f) {
      throw RenderInputError("background colour components must lie in [0, 1]");
    }
  }
  const Material& m = options.material;
  if (!std::isfinite(m.shininess) || m.shininess < 0.0f) {
    throw RenderInputError("material shininess must be finite and non-negative");
  }
}

}  // namespace

struct Renderer::Impl {
  // Declared first so it is destroyed last: everything below lives on its device.
  std::unique_ptr<VulkanContext> context;
  std::unique_ptr<ComputePath> computePath;
  std::unique_ptr<MeshPath> meshPath;
  std::unique_ptr<CrackFillPass> crackFill;
  std::unique_ptr<RenderTargets> targets;
  std::unique_ptr<StageClock> clock;
  SharedFrameBuffers shared;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;

  ~Impl();
  GeometryPath resolvePath(GeometryPath requested) const;
  void ensureTargets(uint32_t width, uint32_t height);
  void uploadShared(const PatchUpload& upload, const FrameUniforms& uniforms);
  void recordGeometry(GeometryPath path, const PatchUpload& upload, const RenderOptions& options);
};

Renderer::Impl::~Impl() {
  if (!context) return;
  vkDeviceWaitIdle(context->device());
  if (fence) vkDestroyFence(context->device(), fence, nullptr);
  if (cmd) vkFreeCommandBuffers(context->device(), context->commandPool(), 1, &cmd);
}

GeometryPath Renderer::Impl::resolvePath(GeometryPath requested) const {
  if (requested == GeometryPath::kAuto) {
    return meshPath ? GeometryPath::kMeshShader : GeometryPath::kCompute;
  }
  if (requested == GeometryPath::kMeshShader && !meshPath) {
    throw RenderUnsupportedError("the mesh-shader path was requested, but device " +
                                 context->info().name + " does not support VK_EXT_mesh_shader");
  }
  return requested;
}

void Renderer::Impl::ensureTargets(uint32_t width, uint32_t height) {
  if (targets && targets->width() == width && targets->height() == height) return;
  targets.reset();  // free the old images before allocating the new ones
  targets = std::make_unique<RenderTargets>(*context, width, height);
  crackFill->bind(*targets);
}

void Renderer::Impl::uploadShared(const PatchUpload& upload, const FrameUniforms& uniforms) {
  VkDeviceSize patchBytes = std::max<VkDeviceSize>(upload.patches.size() * sizeof(GpuPatch), 256);
  if (patchBytes > context->limits().maxStorageBufferRange) {
    throw RenderInputError(
        std::to_string(upload.patches.size()) +
        " patches exceed what this device can read in one frame (" +
        std::to_string(context->limits().maxStorageBufferRange / sizeof(GpuPatch)) + ")");
  }
  if (!shared.patches.handle() || shared.patches.size() < patchBytes) {
    shared.patches =
        GpuBuffer(*context, patchBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::kUpload);
  }
  std::memcpy(shared.patches.mapped(), upload.patches.data(),
              upload.patches.size() * sizeof(GpuPatch));
  std::memcpy(shared.uniforms.mapped(), &uniforms, sizeof(uniforms));
  FrameStats zero{0, 0};
  std::memcpy(shared.stats.mapped(), &zero, sizeof(zero));
  shared.patches.flush();
  shared.uniforms.flush();
  shared.stats.flush();
}

void Renderer::Impl::recordGeometry(GeometryPath path, const PatchUpload& upload,
                                    const RenderOptions& options) {
  if (path == GeometryPath::kMeshShader) {
    meshPath->prepare(shared);
    meshPath->record(cmd, upload, *targets, options.background, *clock);
  } else {
    computePath->prepare(shared, upload);
    computePath->record(cmd, upload, *targets, options.background, *clock);
  }
}

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

Renderer Renderer::create(const DeviceSelection& selection) {
  auto impl = std::make_unique<Impl>();
  impl->context = VulkanContext::create(selection);
  const VulkanContext& context = *impl->context;
  impl->computePath = std::make_unique<ComputePath>(context);
  if (context.info().meshShaders) impl->meshPath = std::make_unique<MeshPath>(context);
  impl->crackFill = std::make_unique<CrackFillPass>(context);
  impl->shared.uniforms = GpuBuffer(context, sizeof(FrameUniforms),
                                    VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, MemoryUse::kUpload);
  impl->shared.stats = GpuBuffer(context, sizeof(FrameStats), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                 MemoryUse::kReadback);

  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = context.commandPool();
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  vkCheck(vkAllocateCommandBuffers(context.device(), &alloc, &impl->cmd),
          "vkAllocateCommandBuffers");
  VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  vkCheck(vkCreateFence(context.device(), &fence, nullptr, &impl->fence), "vkCreateFence");
  impl->clock = std::make_unique<StageClock>(context, impl->cmd, impl->fence);
  return Renderer(std::move(impl));
}

DeviceInfo Renderer::info() const {
  return impl_->context->info();
}

bool Renderer::hasMeshShaders() const {
  return impl_->meshPath != nullptr;
}

uint64_t Renderer::frameMemoryBytes() const {
  const Impl& s = *impl_;
  return (s.targets ? s.targets->bytes() : 0) + s.computePath->geometryBytes() +
         s.shared.patches.size();
}

void Renderer::releaseFrameMemory() {
  Impl& s = *impl_;
  s.targets.reset();  // the crack filler's descriptors are bound again with the next targets
  s.computePath->releaseGeometry();
  s.shared.patches = GpuBuffer();
}

std::vector<std::string> Renderer::takeValidationMessages() {
  return impl_->context->takeValidationMessages();
}

Frame Renderer::render(std::span<const RenderPatch> patches, const Camera& camera,
                       const RenderOptions& options) {
  Clock::time_point hostStart = Clock::now();
  validateCamera(camera);
  validatePatches(patches, options.uniformLevel);
  validateOptions(options);
  Impl& s = *impl_;
  GeometryPath path = s.resolvePath(options.path);
  ViewProjection vp = buildViewProjection(camera, boundsOf(patches));
  BatchLimits limits = path == GeometryPath::kMeshShader ? MeshPath::batchLimits(*s.context)
                                                         : ComputePath::batchLimits(*s.context);
  if (options.maxBatchTriangles != 0) {
    limits.maxTriangles = std::min(limits.maxTriangles, options.maxBatchTriangles);
  }
  PatchUpload upload = planBatches(patches, options.uniformLevel, limits);
  s.ensureTargets(camera.width, camera.height);
  s.uploadShared(upload, makeFrameUniforms(camera, vp, options));

  if (options.checkpoint) options.checkpoint();
  // Stages: setup; per batch tessellation and a raster per band; crack filling per band; readback.
  const uint32_t bands = static_cast<uint32_t>(s.targets->bands().size());
  const uint32_t fillBands =
      static_cast<uint32_t>(s.targets->bands(RenderTargets::kCrackFillBandPixels).size());
  s.clock->begin(static_cast<uint32_t>(upload.batches.size()) * (1 + bands) + fillBands + 4,
                 options.checkpoint);
  s.targets->toAttachments(s.cmd);
  s.recordGeometry(path, upload, options);
  if (options.crackFilling) {
    s.clock->enter(Stage::kCrackFilling);
    s.targets->toCrackFill(s.cmd);
    s.crackFill->record(s.cmd, *s.targets, *s.clock);
  }
  s.clock->enter(Stage::kReadback);
  s.targets->recordReadback(s.cmd, options.crackFilling, options.readPatchIds, *s.clock);
  Frame frame;
  s.clock->finish(frame.timings);

  frame.pathUsed = path;
  frame.batches = static_cast<uint32_t>(upload.batches.size());
  s.shared.stats.invalidate();
  FrameStats stats;
  std::memcpy(&stats, s.shared.stats.mapped(), sizeof(stats));
  frame.patchesCulled = stats.culledPatches;
  frame.trianglesGenerated = stats.triangles;
  s.targets->copyTo(frame, options.readPatchIds, options.checkpoint);
  frame.timings.hostTotalMs = millisecondsSince(hostStart);
  return frame;
}

TessellatedMesh Renderer::tessellate(std::span<const RenderPatch> patches, uint32_t uniformLevel) {
  validatePatches(patches, uniformLevel);
  Impl& s = *impl_;
  PatchUpload upload = planBatches(patches, uniformLevel, ComputePath::batchLimits(*s.context));
  uint64_t vertexCount = 0, triangleCount = 0;
  for (const GeometryBatch& b : upload.batches) {
    vertexCount += b.vertexCount;
    triangleCount += b.triangleCount;
  }
  s.uploadShared(upload, FrameUniforms{});
  s.computePath->prepare(s.shared, upload);
  constexpr VkBufferUsageFlags kDst = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  GpuBuffer vertices(*s.context, std::max<VkDeviceSize>(vertexCount * ComputePath::kVertexBytes, 4),
                     kDst, MemoryUse::kReadback);
  GpuBuffer indices(*s.context,
                    std::max<VkDeviceSize>(triangleCount * ComputePath::kTriangleBytes, 4), kDst,
                    MemoryUse::kReadback);
  s.clock->begin(1);
  s.computePath->recordReadback(s.cmd, upload, vertices, indices);
  StageTimings unused;
  s.clock->finish(unused);
  vertices.invalidate();
  indices.invalidate();

  TessellatedMesh mesh;
  mesh.positions.resize(3 * vertexCount);
  mesh.normals.resize(3 * vertexCount);
  mesh.vertexPatchIds.resize(vertexCount);
  const float* v = static_cast<const float*>(vertices.mapped());
  for (uint64_t i = 0; i < vertexCount; ++i, v += 8) {  // PulledVertex: position+id, normal
    std::copy(v, v + 3, &mesh.positions[3 * i]);
    std::copy(v + 4, v + 7, &mesh.normals[3 * i]);
    std::memcpy(&mesh.vertexPatchIds[i], v + 3, sizeof(uint32_t));
  }
  // Indices are relative to their batch's vertex buffer; make them global.
  mesh.indices.resize(3 * triangleCount);
  const uint32_t* index = static_cast<const uint32_t*>(indices.mapped());
  uint64_t at = 0;
  uint32_t vertexBase = 0;
  for (const GeometryBatch& b : upload.batches) {
    for (uint64_t k = 0; k < 3 * b.triangleCount; ++k, ++at)
      mesh.indices[at] = index[at] + vertexBase;
    vertexBase += static_cast<uint32_t>(b.vertexCount);
  }
  return mesh;
}

}  // namespace tessera::gpu
