#include "gpu/vulkan/device_ranking.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <string>

#include "gpu/vulkan/vulkan_error.h"

namespace tessera::gpu {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string describe(std::span<const DeviceCandidate> candidates) {
  std::string text;
  for (size_t i = 0; i < candidates.size(); ++i) {
    const DeviceCandidate& c = candidates[i];
    text += "\n  [" + std::to_string(i) + "] " + c.name + " (" + deviceKindName(c.kind) + ")";
    if (!c.usable) text += ": unusable, " + c.whyUnusable;
  }
  return text.empty() ? "\n  (none)" : text;
}

size_t chooseOverride(std::span<const DeviceCandidate> candidates,
                      const DeviceSelection& selection) {
  if (selection.index >= 0) {
    size_t i = static_cast<size_t>(selection.index);
    if (i >= candidates.size() || !candidates[i].usable) {
      throw RenderUnsupportedError("Vulkan device index " + std::to_string(selection.index) +
                                   " is not a usable device; devices:" + describe(candidates));
    }
    return i;
  }
  std::string wanted = lower(selection.nameContains);
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (candidates[i].usable && lower(candidates[i].name).find(wanted) != std::string::npos) {
      return i;
    }
  }
  throw RenderUnsupportedError("no usable Vulkan device name contains \"" + selection.nameContains +
                               "\"; devices:" + describe(candidates));
}

}  // namespace

const char* deviceKindName(DeviceKind kind) {
  switch (kind) {
    case DeviceKind::kDiscrete:
      return "discrete GPU";
    case DeviceKind::kIntegrated:
      return "integrated GPU";
    case DeviceKind::kVirtual:
      return "virtual GPU";
    case DeviceKind::kCpu:
      return "CPU";
    case DeviceKind::kOther:
      return "other";
  }
  return "other";
}

int deviceRank(const DeviceCandidate& candidate) {
  switch (candidate.kind) {
    case DeviceKind::kDiscrete:
      return candidate.vendorId == kVendorNvidia ? 0 : 1;
    case DeviceKind::kIntegrated:
      return 2;
    case DeviceKind::kVirtual:
      return 3;
    case DeviceKind::kCpu:
      return 4;
    case DeviceKind::kOther:
      return 5;
  }
  return 5;
}

size_t chooseDevice(std::span<const DeviceCandidate> candidates, const DeviceSelection& selection) {
  if (selection.index >= 0 || !selection.nameContains.empty()) {
    return chooseOverride(candidates, selection);
  }
  size_t best = candidates.size();
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (!candidates[i].usable) continue;
    // Ties keep enumeration order, so the choice is stable across runs.
    if (best == candidates.size() || deviceRank(candidates[i]) < deviceRank(candidates[best])) {
      best = i;
    }
  }
  if (best == candidates.size()) {
    throw RenderUnsupportedError("no usable Vulkan 1.3 device; devices:" + describe(candidates));
  }
  return best;
}

DeviceSelection DeviceSelection::fromEnvironment() {
  DeviceSelection selection;
  if (const char* device = std::getenv("TESSERA_VK_DEVICE"); device && *device) {
    std::string value = device;
    bool digits = std::all_of(value.begin(), value.end(),
                              [](unsigned char c) { return std::isdigit(c) != 0; });
    if (digits && value.size() < 9)
      selection.index = std::stoi(value);
    else
      selection.nameContains = value;
  }
  if (const char* validation = std::getenv("TESSERA_VK_VALIDATION")) {
    selection.validation = std::string(validation) == "1";
  }
  return selection;
}

}  // namespace tessera::gpu
