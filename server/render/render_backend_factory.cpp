#include "server/render/render_backend_factory.h"

#if TESSERA_WITH_RENDER
#include "server/render/render_vulkan_backend.h"
#endif

namespace tessera::server {
namespace {

#if !TESSERA_WITH_RENDER
// Builds without gpu/vulkan (TESSERA_BUILD_VULKAN=OFF) or without OpenImageIO.
class UnavailableRenderBackend final : public RenderBackend {
 public:
  std::string name() const override { return "vulkan"; }
  bool available() const override { return false; }
  std::string detail() const override { return kWhy; }
  std::string device() const override { return {}; }
  int64_t frameBytes(int, int) const override { return 0; }
  RenderedFrame render(const ControlMesh&, const FrameJob&, const CancellationToken&) override {
    throw RenderUnavailable(kWhy);
  }

 private:
  static constexpr const char* kWhy =
      "this server was built without the Vulkan renderer (TESSERA_BUILD_VULKAN=OFF, or Vulkan "
      "or OpenImageIO not found), so it cannot render frames";
};
#endif

}  // namespace

std::unique_ptr<RenderBackend> makeRenderBackend(PatchSetCache& patches, bool probeDevice) {
#if TESSERA_WITH_RENDER
  return std::make_unique<VulkanRenderBackend>(
      patches, gpu::DeviceSelection::fromEnvironment(), probeDevice);
#else
  (void)patches, (void)probeDevice;
  return std::make_unique<UnavailableRenderBackend>();
#endif
}

}  // namespace tessera::server
