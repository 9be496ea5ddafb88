#include "gpu/vulkan/compute_path.h"

#include <algorithm>

#include "gpu/vulkan/barriers.h"
#include "gpu/vulkan/pipeline_builders.h"
#include "gpu/vulkan/vulkan_context.h"

namespace tessera::gpu {
namespace {

constexpr VkDeviceSize kDrawBytes = 16;  // VkDrawIndirectCommand
constexpr VkDeviceSize kBufferBudget = 512ull << 20;
constexpr uint32_t kMaxGroupsPerDimension = 65535;

constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
constexpr VkDescriptorType kUniform = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
constexpr VkShaderStageFlags kCompute = VK_SHADER_STAGE_COMPUTE_BIT;
constexpr VkShaderStageFlags kVertex = VK_SHADER_STAGE_VERTEX_BIT;
constexpr VkShaderStageFlags kVertexFragment = kVertex | VK_SHADER_STAGE_FRAGMENT_BIT;

constexpr Access kTessellationWrites{VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                                     VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT};
constexpr Access kRasterReads{
    VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT,
    VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT};

// Grows `buffer` to hold `bytes` (with headroom, to avoid re-allocating every frame).
void ensureSize(const VulkanContext& context, GpuBuffer& buffer, VkDeviceSize bytes,
                VkBufferUsageFlags usage, VkDeviceSize cap) {
  bytes = std::max<VkDeviceSize>(bytes, 256);
  if (buffer.handle() && buffer.size() >= bytes) return;
  VkDeviceSize size = std::min(cap, std::max(bytes, bytes + bytes / 4));
  buffer = GpuBuffer(context, size, usage, MemoryUse::kDeviceOnly);
}

struct BatchPush {
  uint32_t firstPatch;
  uint32_t patchCount;
  uint32_t cullPatches;
};

constexpr Access kTransferRead{VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT};
constexpr Access kTransferWrite{VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT};
constexpr Access kHostRead{VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT};

}  // namespace

ComputePath::ComputePath(const VulkanContext& context)
    : context_(context), device_(context.device()) {
  tessellateSetLayout_ = createSetLayout(device_, {{0, kStorage, kCompute},
                                                   {1, kStorage, kCompute},
                                                   {2, kStorage, kCompute},
                                                   {3, kStorage, kCompute},
                                                   {4, kStorage, kCompute},
                                                   {5, kUniform, kCompute}});
  rasterSetLayout_ = createSetLayout(
      device_, {{0, kStorage, kVertex}, {1, kStorage, kVertex}, {2, kUniform, kVertexFragment}});
  tessellateLayout_ =
      createPipelineLayout(device_, tessellateSetLayout_, sizeof(BatchPush), kCompute);
  rasterLayout_ = createPipelineLayout(device_, rasterSetLayout_, 0, 0);
  tessellatePipeline_ =
      createComputePipeline(device_, tessellateLayout_, ShaderId::kTessellateComp);
  rasterPipeline_ = createGraphicsPipeline(device_, rasterLayout_,
                                           {{VK_SHADER_STAGE_VERTEX_BIT, ShaderId::kPulledVert},
                                            {VK_SHADER_STAGE_FRAGMENT_BIT, ShaderId::kShadeFrag}},
                                           RenderTargets::formats());
  pool_ = createPool(device_, 2, {kStorage, kUniform}, 6);
  tessellateSet_ = allocateSet(device_, pool_, tessellateSetLayout_);
  rasterSet_ = allocateSet(device_, pool_, rasterSetLayout_);
}

ComputePath::~ComputePath() {
  vkDestroyDescriptorPool(device_, pool_, nullptr);
  vkDestroyPipeline(device_, rasterPipeline_, nullptr);
  vkDestroyPipeline(device_, tessellatePipeline_, nullptr);
  vkDestroyPipelineLayout(device_, rasterLayout_, nullptr);
  vkDestroyPipelineLayout(device_, tessellateLayout_, nullptr);
  vkDestroyDescriptorSetLayout(device_, rasterSetLayout_, nullptr);
  vkDestroyDescriptorSetLayout(device_, tessellateSetLayout_, nullptr);
}

BatchLimits ComputePath::batchLimits(const VulkanContext& context) {
  VkDeviceSize cap = std::min<VkDeviceSize>(context.limits().maxStorageBufferRange, kBufferBudget);
  BatchLimits limits;
  limits.maxVertices = cap / kVertexBytes;
  limits.maxTriangles = cap / kTriangleBytes;
  limits.maxPatches = static_cast<uint32_t>(
      std::min<uint64_t>({cap / kDrawBytes, context.limits().maxDrawIndirectCount, 1u << 20}));
  return limits;
}

void ComputePath::prepare(const SharedFrameBuffers& shared, const PatchUpload& upload) {
  VkDeviceSize cap = std::min<VkDeviceSize>(context_.limits().maxStorageBufferRange, kBufferBudget);
  uint32_t maxPatches = 0;
  for (const GeometryBatch& b : upload.batches) maxPatches = std::max(maxPatches, b.patchCount);
  constexpr VkBufferUsageFlags kGeometry =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
  ensureSize(context_, vertices_, upload.largestBatchVertices * kVertexBytes, kGeometry, cap);
  ensureSize(context_, indices_, upload.largestBatchTriangles * kTriangleBytes, kGeometry, cap);
  ensureSize(context_, draws_, VkDeviceSize(maxPatches) * kDrawBytes,
             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT, cap);

  writeBufferDescriptor(device_, tessellateSet_, 0, kStorage, shared.patches.handle());
  writeBufferDescriptor(device_, tessellateSet_, 1, kStorage, vertices_.handle());
  writeBufferDescriptor(device_, tessellateSet_, 2, kStorage, indices_.handle());
  writeBufferDescriptor(device_, tessellateSet_, 3, kStorage, draws_.handle());
  writeBufferDescriptor(device_, tessellateSet_, 4, kStorage, shared.stats.handle());
  writeBufferDescriptor(device_, tessellateSet_, 5, kUniform, shared.uniforms.handle());
  writeBufferDescriptor(device_, rasterSet_, 0, kStorage, vertices_.handle());
  writeBufferDescriptor(device_, rasterSet_, 1, kStorage, indices_.handle());
  writeBufferDescriptor(device_, rasterSet_, 2, kUniform, shared.uniforms.handle());
}

VkDeviceSize ComputePath::geometryBytes() const {
  return vertices_.size() + indices_.size() + draws_.size();
}

void ComputePath::releaseGeometry() {
  vertices_ = GpuBuffer();
  indices_ = GpuBuffer();
  draws_ = GpuBuffer();
}

void ComputePath::record(VkCommandBuffer cmd, const PatchUpload& upload,
                         const RenderTargets& targets, const std::array<float, 4>& background,
                         StageClock& clock) const {
  if (upload.batches.empty()) {  // still clear the targets
    targets.beginRendering(cmd, true, background);
    targets.endRendering(cmd);
    return;
  }
  for (size_t b = 0; b < upload.batches.size(); ++b) {
    const GeometryBatch& batch = upload.batches[b];
    // The previous batch's draws must have read the buffers before they are overwritten.
    if (b > 0) memoryBarrier(cmd, kRasterReads, kTessellationWrites);
    clock.enter(Stage::kTessellation);
    recordTessellation(cmd, batch, true);
    memoryBarrier(cmd, kTessellationWrites, kRasterReads);
    // Band by band (one band up to 8 M pixels): each draws the whole batch, scissored to its rows.
    for (const RenderTargets::RowBand& band : targets.bands()) {
      clock.enter(Stage::kRaster);
      targets.beginRendering(cmd, b == 0, background, band);
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rasterPipeline_);
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rasterLayout_, 0, 1,
                              &rasterSet_, 0, nullptr);
      vkCmdDrawIndirect(cmd, draws_.handle(), 0, batch.patchCount,
                        static_cast<uint32_t>(kDrawBytes));
      targets.endRendering(cmd);
    }
  }
}

void ComputePath::recordTessellation(VkCommandBuffer cmd, const GeometryBatch& batch,
                                     bool cull) const {
  BatchPush push{batch.firstPatch, batch.patchCount, cull ? 1u : 0u};
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tessellatePipeline_);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tessellateLayout_, 0, 1,
                          &tessellateSet_, 0, nullptr);
  vkCmdPushConstants(cmd, tessellateLayout_, kCompute, 0, sizeof(push), &push);
  uint32_t groupsX = std::min(batch.patchCount, kMaxGroupsPerDimension);
  uint32_t groupsY = (batch.patchCount + groupsX - 1) / groupsX;
  vkCmdDispatch(cmd, groupsX, groupsY, 1);
}

void ComputePath::recordReadback(VkCommandBuffer cmd, const PatchUpload& upload,
                                 const GpuBuffer& vertices, const GpuBuffer& indices) const {
  VkDeviceSize vertexOffset = 0;
  VkDeviceSize triangleOffset = 0;
  for (size_t b = 0; b < upload.batches.size(); ++b) {
    const GeometryBatch& batch = upload.batches[b];
    if (b > 0) memoryBarrier(cmd, kTransferRead, kTessellationWrites);
    recordTessellation(cmd, batch, false);
    memoryBarrier(cmd, kTessellationWrites, kTransferRead);
    VkBufferCopy vertexCopy{0, vertexOffset * kVertexBytes, batch.vertexCount * kVertexBytes};
    VkBufferCopy indexCopy{0, triangleOffset * kTriangleBytes,
                           batch.triangleCount * kTriangleBytes};
    if (vertexCopy.size)
      vkCmdCopyBuffer(cmd, vertices_.handle(), vertices.handle(), 1, &vertexCopy);
    if (indexCopy.size) vkCmdCopyBuffer(cmd, indices_.handle(), indices.handle(), 1, &indexCopy);
    vertexOffset += batch.vertexCount;
    triangleOffset += batch.triangleCount;
  }
  memoryBarrier(cmd, kTransferWrite, kHostRead);
}

}  // namespace tessera::gpu
