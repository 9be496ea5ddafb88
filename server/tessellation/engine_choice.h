// Which tessellation engine the server runs (--engine): the CPU's, or the CUDA engine where this
// build has CUDA and a device answers; its metrics.
#pragma once

#include <memory>
#include <string>

#include "server/meshes/patch_set_cache.h"
#include "server/operations/metrics.h"
#include "server/tessellation/tessellation_engine.h"

namespace tessera::server {

// `wanted`: "cpu", "cuda" or "auto" (cuda when it can be had, else cpu, saying why in the
// engine's detail). Throws std::runtime_error naming --engine when "cuda" cannot be had (a build
// without CUDA, or no device, in CUDA's words).
std::unique_ptr<TessellationEngine> chooseEngine(const std::string& wanted, size_t deviceCacheBytes,
                                                 PatchSetCache& patches);

// tessera_engine_info{engine, device}; for the CUDA engine also its device cache and the jobs
// whose vertices went to the CPU for want of device memory.
void registerEngineMetrics(MetricsRegistry& registry, const TessellationEngine& engine);

}  // namespace tessera::server
