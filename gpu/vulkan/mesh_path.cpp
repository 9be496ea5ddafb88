#include "gpu/vulkan/mesh_path.h"

#include <algorithm>

#include "gpu/vulkan/pipeline_builders.h"
#include "gpu/vulkan/vulkan_context.h"
#include "gpu/vulkan/vulkan_error.h"

namespace tessera::gpu {
namespace {

constexpr uint32_t kTaskPatches = 32;  // patches per task workgroup (meshlet_layout.glsl)
constexpr VkShaderStageFlags kTask = VK_SHADER_STAGE_TASK_BIT_EXT;
constexpr VkShaderStageFlags kMesh = VK_SHADER_STAGE_MESH_BIT_EXT;
constexpr VkShaderStageFlags kFragment = VK_SHADER_STAGE_FRAGMENT_BIT;

struct BatchPush {
  uint32_t firstPatch;
  uint32_t patchCount;
};

}  // namespace

MeshPath::MeshPath(const VulkanContext& context)
    : device_(context.device()), drawMeshTasks_(context.drawMeshTasks()) {
  if (!context.info().meshShaders || !drawMeshTasks_) {
    throw RenderUnsupportedError("device " + context.info().name +
                                 " does not support VK_EXT_mesh_shader");
  }
  constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  constexpr VkDescriptorType kUniform = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
  setLayout_ = createSetLayout(device_, {{0, kStorage, kTask | kMesh},
                                         {1, kStorage, kTask},
                                         {2, kUniform, kTask | kMesh | kFragment}});
  layout_ = createPipelineLayout(device_, setLayout_, sizeof(BatchPush), kTask);
  pipeline_ = createGraphicsPipeline(device_, layout_,
                                     {{VK_SHADER_STAGE_TASK_BIT_EXT, ShaderId::kPatchesTask},
                                      {VK_SHADER_STAGE_MESH_BIT_EXT, ShaderId::kPatchesMesh},
                                      {VK_SHADER_STAGE_FRAGMENT_BIT, ShaderId::kShadeMeshFrag}},
                                     RenderTargets::formats());
  pool_ = createPool(device_, 1, {kStorage, kUniform}, 2);
  set_ = allocateSet(device_, pool_, setLayout_);
}

MeshPath::~MeshPath() {
  vkDestroyDescriptorPool(device_, pool_, nullptr);
  vkDestroyPipeline(device_, pipeline_, nullptr);
  vkDestroyPipelineLayout(device_, layout_, nullptr);
  vkDestroyDescriptorSetLayout(device_, setLayout_, nullptr);
}

BatchLimits MeshPath::batchLimits(const VulkanContext& context) {
  VkPhysicalDeviceMeshShaderPropertiesEXT props{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_PROPERTIES_EXT};
  VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &props};
  vkGetPhysicalDeviceProperties2(context.physicalDevice(), &p2);
  BatchLimits limits;
  uint64_t groups = std::min(props.maxTaskWorkGroupCount[0], props.maxTaskWorkGroupTotalCount);
  limits.maxPatches = static_cast<uint32_t>(std::min<uint64_t>(groups * kTaskPatches, 1u << 22));
  return limits;
}

void MeshPath::prepare(const SharedFrameBuffers& shared) {
  writeBufferDescriptor(device_, set_, 0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                        shared.patches.handle());
  writeBufferDescriptor(device_, set_, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, shared.stats.handle());
  writeBufferDescriptor(device_, set_, 2, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                        shared.uniforms.handle());
}

void MeshPath::record(VkCommandBuffer cmd, const PatchUpload& upload, const RenderTargets& targets,
                      const std::array<float, 4>& background, StageClock& clock) const {
  if (upload.batches.empty()) {
    targets.beginRendering(cmd, true, background);
    targets.endRendering(cmd);
    return;
  }
  for (size_t b = 0; b < upload.batches.size(); ++b) {
    const GeometryBatch& batch = upload.batches[b];
    clock.enter(Stage::kRaster);  // tessellation runs inside the mesh shaders
    targets.beginRendering(cmd, b == 0, background);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_, 0, 1, &set_, 0, nullptr);
    BatchPush push{batch.firstPatch, batch.patchCount};
    vkCmdPushConstants(cmd, layout_, kTask, 0, sizeof(push), &push);
    drawMeshTasks_(cmd, (batch.patchCount + kTaskPatches - 1) / kTaskPatches, 1, 1);
    targets.endRendering(cmd);
  }
}

}  // namespace tessera::gpu
