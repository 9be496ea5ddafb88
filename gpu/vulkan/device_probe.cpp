#include "gpu/vulkan/device_probe.h"

#include <vulkan/vulkan.h>

#include <memory>
#include <vector>

#include "gpu/vulkan/device_ranking.h"
#include "gpu/vulkan/physical_device_queries.h"
#include "gpu/vulkan/vulkan_error.h"

namespace tessera::gpu {
namespace {

struct InstanceDeleter {
  void operator()(VkInstance instance) const { vkDestroyInstance(instance, nullptr); }
};
using Instance = std::unique_ptr<std::remove_pointer_t<VkInstance>, InstanceDeleter>;

}  // namespace

ProbedDevice probeRenderDevice(const DeviceSelection& selection) {
  // Value-initialised, then sType set: -Wextra flags partial aggregate initialisers.
  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "tessera-server";
  app.apiVersion = VK_API_VERSION_1_3;
  VkInstanceCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  info.pApplicationInfo = &app;
  VkInstance raw = VK_NULL_HANDLE;
  vkCheck(vkCreateInstance(&info, nullptr, &raw), "vkCreateInstance");
  Instance instance(raw);

  const std::vector<VkPhysicalDevice> devices = physicalDevices(raw);
  std::vector<DeviceCandidate> candidates;
  for (VkPhysicalDevice device : devices)
    candidates.push_back(candidateOf(device, missingBasics(device)));
  size_t chosen = chooseDevice(candidates, selection);

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
  out.meshShaderExtension = hasDeviceExtension(devices[chosen], VK_EXT_MESH_SHADER_EXTENSION_NAME);
  return out;
}

}  // namespace tessera::gpu
