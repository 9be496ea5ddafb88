// The CPU tessellation engine: core's preprocessing, planning, watertight triangulation and
// GLB writer, behind the server's TessellationEngine seam. Preprocessed patch sets are cached
// per mesh (keyed by mesh id and content hash) within a byte budget.
#pragma once

#include <memory>
#include <string>

#include "core/patch_set.h"
#include "server/lru_cache.h"
#include "server/tessellation_engine.h"

namespace tessera::server {

class CpuTessellationEngine : public TessellationEngine {
 public:
  explicit CpuTessellationEngine(size_t patchCacheBytes);
  std::string name() const override { return "cpu"; }
  bool available() const override { return true; }
  std::string detail() const override;
  TessellationOutput run(const ControlMesh& mesh, const TessellationJob& job,
                         const CancellationToken& cancel) override;

 private:
  std::shared_ptr<const PatchSet> patchesFor(const ControlMesh& mesh, const TessellationJob& job);
  LruCache<std::string, PatchSet> patches_;
};

}  // namespace tessera::server
