#include "gpu/vulkan/shader_library.h"

#include <cstddef>

#include "gpu/vulkan/vulkan_error.h"

namespace tessera::gpu {
namespace spirv {
#define TESSERA_DECLARE_SPIRV(symbol)  \
  extern const std::uint32_t symbol[]; \
  extern const std::size_t symbol##Words;
TESSERA_DECLARE_SPIRV(kTessellateComp)
TESSERA_DECLARE_SPIRV(kPulledVert)
TESSERA_DECLARE_SPIRV(kShadeFrag)
TESSERA_DECLARE_SPIRV(kShadeMeshFrag)
TESSERA_DECLARE_SPIRV(kPatchesTask)
TESSERA_DECLARE_SPIRV(kPatchesMesh)
TESSERA_DECLARE_SPIRV(kCrackFillComp)
#undef TESSERA_DECLARE_SPIRV
}  // namespace spirv

std::span<const uint32_t> shaderCode(ShaderId id) {
  using namespace spirv;
  switch (id) {
    case ShaderId::kTessellateComp:
      return {kTessellateComp, kTessellateCompWords};
    case ShaderId::kPulledVert:
      return {kPulledVert, kPulledVertWords};
    case ShaderId::kShadeFrag:
      return {kShadeFrag, kShadeFragWords};
    case ShaderId::kShadeMeshFrag:
      return {kShadeMeshFrag, kShadeMeshFragWords};
    case ShaderId::kPatchesTask:
      return {kPatchesTask, kPatchesTaskWords};
    case ShaderId::kPatchesMesh:
      return {kPatchesMesh, kPatchesMeshWords};
    case ShaderId::kCrackFillComp:
      return {kCrackFillComp, kCrackFillCompWords};
  }
  return {};
}

VkShaderModule createShaderModule(VkDevice device, ShaderId id) {
  std::span<const uint32_t> code = shaderCode(id);
  VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  info.codeSize = code.size_bytes();
  info.pCode = code.data();
  VkShaderModule module = VK_NULL_HANDLE;
  vkCheck(vkCreateShaderModule(device, &info, nullptr, &module), "vkCreateShaderModule");
  return module;
}

}  // namespace tessera::gpu
