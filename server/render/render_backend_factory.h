// The render backend of this build: builds with the Vulkan renderer and OpenImageIO get the Vulkan
// backend (render_vulkan_backend.h); others get one that refuses every frame with
// RenderUnavailable, which the service answers as UNIMPLEMENTED.
#pragma once

#include <memory>

#include "server/render/render_backend.h"
#include "server/meshes/patch_set_cache.h"

namespace tessera::server {

// The Vulkan backend when this build has one, else one that is unavailable and says why.
// Patch sets come from the server's shared cache. probeDevice: find out at once which
// device the renderer will use (instance and device only; the renderer itself is created at the
// first frame), so that GetServerInfo can name it.
std::unique_ptr<RenderBackend> makeRenderBackend(PatchSetCache& patches, bool probeDevice);

}  // namespace tessera::server
