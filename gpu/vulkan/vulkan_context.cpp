#include "gpu/vulkan/vulkan_context.h"

#include <cstdio>
#include <cstring>
#include <utility>

#include "gpu/vulkan/device_ranking.h"
#include "gpu/vulkan/physical_device_queries.h"
#include "gpu/vulkan/vulkan_error.h"

namespace tessera::gpu {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
// What the mesh shaders are compiled for (shaders/include/meshlet_layout.glsl).
constexpr uint32_t kMeshletVertices = 192;
constexpr uint32_t kMeshletPrimitives = 64;
constexpr uint32_t kMeshWorkgroupSize = 32;
constexpr uint32_t kMaxMeshletsPerTaskGroup = 32 * 128;  // 32 patches × 8192/64 meshlets

bool hasLayer(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  for (const VkLayerProperties& l : layers) {
    if (std::strcmp(l.layerName, name) == 0) return true;
  }
  return false;
}

// Empty when the device has what the compute path needs, else the reason it does not.
std::string missingRequirement(VkPhysicalDevice device) {
  if (std::string basics = missingBasics(device); !basics.empty()) return basics;
  VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f13};
  vkGetPhysicalDeviceFeatures2(device, &f2);
  if (!f13.dynamicRendering) return "no dynamicRendering";
  if (!f13.synchronization2) return "no synchronization2";
  if (!f13.maintenance4) return "no maintenance4";  // glslc's SPIR-V 1.6 uses LocalSizeId
  if (!f2.features.multiDrawIndirect) return "no multiDrawIndirect";
  return {};
}

struct MeshSupport {
  bool usable = false;
  uint32_t maxVertices = 0;
  uint32_t maxPrimitives = 0;
};

MeshSupport meshSupport(VkPhysicalDevice device) {
  MeshSupport support;
  if (!hasDeviceExtension(device, VK_EXT_MESH_SHADER_EXTENSION_NAME)) return support;
  VkPhysicalDeviceMeshShaderFeaturesEXT features{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_FEATURES_EXT};
  VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &features};
  vkGetPhysicalDeviceFeatures2(device, &f2);
  VkPhysicalDeviceMeshShaderPropertiesEXT props{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_PROPERTIES_EXT};
  VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &props};
  vkGetPhysicalDeviceProperties2(device, &p2);
  support.maxVertices = props.maxMeshOutputVertices;
  support.maxPrimitives = props.maxMeshOutputPrimitives;
  support.usable = features.taskShader && features.meshShader &&
                   props.maxMeshOutputVertices >= kMeshletVertices &&
                   props.maxMeshOutputPrimitives >= kMeshletPrimitives &&
                   props.maxMeshWorkGroupInvocations >= kMeshWorkgroupSize &&
                   props.maxTaskWorkGroupInvocations >= kMeshWorkgroupSize &&
                   props.maxMeshWorkGroupCount[0] >= kMaxMeshletsPerTaskGroup;
  return support;
}

}  // namespace

std::unique_ptr<VulkanContext> VulkanContext::create(const DeviceSelection& selection) {
  std::unique_ptr<VulkanContext> context(new VulkanContext());
  context->createInstance(selection.validation);
  context->pickPhysicalDevice(selection);
  context->createDevice();
  return context;
}

VulkanContext::~VulkanContext() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    if (commandPool_) vkDestroyCommandPool(device_, commandPool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  // Leaked objects are reported while the device is destroyed, after anyone could ask for
  // the messages: print them, as validation is a debugging aid anyway.
  for (const std::string& m : messages_)
    std::fprintf(stderr, "tessera_vulkan validation: %s\n", m.c_str());
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

void VulkanContext::createInstance(bool wantValidation) {
  bool validation = wantValidation && hasLayer(kValidationLayer);
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "tessera";
  app.pEngineName = "tessera_vulkan";
  app.apiVersion = VK_API_VERSION_1_3;
  std::vector<const char*> layers;
  std::vector<const char*> extensions;
  if (validation) {
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &app;
  info.enabledLayerCount = static_cast<uint32_t>(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  vkCheck(vkCreateInstance(&info, nullptr, &instance_), "vkCreateInstance");
  info_.validation = validation;
  if (!validation) return;

  VkDebugUtilsMessengerCreateInfoEXT messenger{
      VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                              VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger.messageType =
      VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT;
  messenger.pfnUserCallback = &VulkanContext::onValidationMessage;
  messenger.pUserData = this;
  auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
      vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
  if (create) {
    vkCheck(create(instance_, &messenger, nullptr, &messenger_), "vkCreateDebugUtilsMessengerEXT");
  }
}

void VulkanContext::pickPhysicalDevice(const DeviceSelection& selection) {
  const std::vector<VkPhysicalDevice> devices = physicalDevices(instance_);
  std::vector<DeviceCandidate> candidates;
  for (VkPhysicalDevice d : devices) candidates.push_back(candidateOf(d, missingRequirement(d)));
  size_t chosen = chooseDevice(candidates, selection);
  physical_ = devices[chosen];

  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &driver};
  vkGetPhysicalDeviceProperties2(physical_, &p2);
  limits_ = p2.properties.limits;
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
  queueFamily_ = static_cast<uint32_t>(graphicsComputeFamily(physical_));

  info_.name = p2.properties.deviceName;
  info_.driver = std::string(driver.driverName) + " " + driver.driverInfo;
  info_.index = static_cast<uint32_t>(chosen);
  info_.vendorId = p2.properties.vendorID;
  info_.deviceId = p2.properties.deviceID;
  info_.kind = candidates[chosen].kind;
  info_.apiVersion = p2.properties.apiVersion;
  MeshSupport mesh = meshSupport(physical_);
  info_.meshShaders = mesh.usable;
  info_.maxMeshOutputVertices = mesh.maxVertices;
  info_.maxMeshOutputPrimitives = mesh.maxPrimitives;

  uint32_t familyCount = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical_, &familyCount, nullptr);
  std::vector<VkQueueFamilyProperties> families(familyCount);
  vkGetPhysicalDeviceQueueFamilyProperties(physical_, &familyCount, families.data());
  info_.timestamps =
      families[queueFamily_].timestampValidBits > 0 && limits_.timestampPeriod > 0.0f;
}

void VulkanContext::createDevice() {
  float priority = 1.0f;
  VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queueInfo.queueFamilyIndex = queueFamily_;
  queueInfo.queueCount = 1;
  queueInfo.pQueuePriorities = &priority;

  VkPhysicalDeviceMeshShaderFeaturesEXT mesh{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_FEATURES_EXT};
  mesh.taskShader = VK_TRUE;
  mesh.meshShader = VK_TRUE;
  VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  f13.dynamicRendering = VK_TRUE;
  f13.synchronization2 = VK_TRUE;
  f13.maintenance4 = VK_TRUE;
  f13.pNext = info_.meshShaders ? &mesh : nullptr;
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f13};
  features.features.multiDrawIndirect = VK_TRUE;

  std::vector<const char*> extensions;
  if (info_.meshShaders) extensions.push_back(VK_EXT_MESH_SHADER_EXTENSION_NAME);
  VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features};
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queueInfo;
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  vkCheck(vkCreateDevice(physical_, &info, nullptr, &device_), "vkCreateDevice");
  vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);
  if (info_.meshShaders) {
    drawMeshTasks_ = reinterpret_cast<PFN_vkCmdDrawMeshTasksEXT>(
        vkGetDeviceProcAddr(device_, "vkCmdDrawMeshTasksEXT"));
    info_.meshShaders = drawMeshTasks_ != nullptr;
  }

  VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool.queueFamilyIndex = queueFamily_;
  vkCheck(vkCreateCommandPool(device_, &pool, nullptr, &commandPool_), "vkCreateCommandPool");
}

std::vector<std::string> VulkanContext::takeValidationMessages() {
  std::lock_guard lock(messagesMutex_);
  return std::exchange(messages_, {});
}

VKAPI_ATTR VkBool32 VKAPI_CALL VulkanContext::onValidationMessage(
    VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
    const VkDebugUtilsMessengerCallbackDataEXT* data, void* self) {
  auto* context = static_cast<VulkanContext*>(self);
  std::lock_guard lock(context->messagesMutex_);
  context->messages_.emplace_back(data && data->pMessage ? data->pMessage : "(no message)");
  return VK_FALSE;
}

}  // namespace tessera::gpu
