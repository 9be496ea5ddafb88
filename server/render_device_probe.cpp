#include "server/render_device_probe.h"

#include <vulkan/vulkan.h>

#include <cstring>
#include <memory>
#include <vector>

#include "gpu/vulkan/device_ranking.h"
#include "gpu/vulkan/vulkan_error.h"

namespace tessera::server {
namespace {

gpu::DeviceKind kindOf(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return gpu::DeviceKind::kDiscrete;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return gpu::DeviceKind::kIntegrated;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return gpu::DeviceKind::kVirtual;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return gpu::DeviceKind::kCpu;
    default:
      return gpu::DeviceKind::kOther;
  }
}

bool hasGraphicsComputeQueue(VkPhysicalDevice device) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  const VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
  for (const VkQueueFamilyProperties& f : families) {
    if ((f.queueFlags & need) == need) return true;
  }
  return false;
}

bool hasExtension(VkPhysicalDevice device, const char* name) {
  uint32_t count = 0;
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data());
  for (const VkExtensionProperties& e : extensions) {
    if (std::strcmp(e.extensionName, name) == 0) return true;
  }
  return false;
}

struct InstanceDeleter {
  void operator()(VkInstance instance) const { vkDestroyInstance(instance, nullptr); }
};
using Instance = std::unique_ptr<std::remove_pointer_t<VkInstance>, InstanceDeleter>;

}  // namespace

ProbedDevice probeRenderDevice(const gpu::DeviceSelection& selection) {
  // Value-initialised, then sType set: -Wextra flags partial aggregate initialisers.
  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "tessera-server";
  app.apiVersion = VK_API_VERSION_1_3;
  VkInstanceCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  info.pApplicationInfo = &app;
  VkInstance raw = VK_NULL_HANDLE;
  gpu::vkCheck(vkCreateInstance(&info, nullptr, &raw), "vkCreateInstance");
  Instance instance(raw);

  uint32_t count = 0;
  gpu::vkCheck(vkEnumeratePhysicalDevices(raw, &count, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devices(count);
  gpu::vkCheck(vkEnumeratePhysicalDevices(raw, &count, devices.data()),
               "vkEnumeratePhysicalDevices");
  std::vector<gpu::DeviceCandidate> candidates;
  for (VkPhysicalDevice device : devices) {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(device, &props);
    gpu::DeviceCandidate c;
    c.name = props.deviceName;
    c.vendorId = props.vendorID;
    c.kind = kindOf(props.deviceType);
    if (props.apiVersion < VK_API_VERSION_1_3)
      c.whyUnusable = "Vulkan 1.3 required";
    else if (!hasGraphicsComputeQueue(device))
      c.whyUnusable = "no graphics+compute queue";
    c.usable = c.whyUnusable.empty();
    candidates.push_back(c);
  }
  size_t chosen = gpu::chooseDevice(candidates, selection);

  VkPhysicalDeviceDriverProperties driver{};
  driver.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES;
  VkPhysicalDeviceProperties2 props2{};
  props2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
  props2.pNext = &driver;
  vkGetPhysicalDeviceProperties2(devices[chosen], &props2);
  ProbedDevice out;
  out.name = candidates[chosen].name;
  out.driver = std::string(driver.driverName) + " " + driver.driverInfo;
  out.kind = candidates[chosen].kind;
  out.meshShaderExtension = hasExtension(devices[chosen], VK_EXT_MESH_SHADER_EXTENSION_NAME);
  return out;
}

}  // namespace tessera::server
