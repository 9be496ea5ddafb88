// The CPU tessellation engine: core's preprocessing, planning, watertight triangulation and
// GLB writer, behind the server's TessellationEngine seam. Preprocessed patch sets come from the
// server's shared PatchSetCache.
#pragma once

#include <memory>
#include <string>

#include "core/patch_set.h"
#include "server/meshes/patch_set_cache.h"
#include "server/tessellation/tessellation_engine.h"

namespace tessera::server {

class CpuTessellationEngine : public TessellationEngine {
 public:
  explicit CpuTessellationEngine(PatchSetCache& patches) : patches_(patches) {}
  std::string name() const override { return "cpu"; }
  bool available() const override { return true; }
  std::string detail() const override;
  TessellationOutput run(const ControlMesh& mesh, const TessellationJob& job,
                         const CancellationToken& cancel) override;

 private:
  PatchSetCache& patches_;
};

}  // namespace tessera::server
