// The CPU tessellation engine: core's preprocessing, planning, watertight triangulation and
// GLB writer, behind the server's TessellationEngine seam. Preprocessed patch sets come from the
// server's shared PatchSetCache.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <utility>

#include "core/rings/patch_set.h"
#include "core/stitching/vertex_evaluation.h"
#include "server/meshes/patch_set_cache.h"
#include "server/tessellation/tessellation_engine.h"

namespace tessera::server {

class CpuTessellationEngine : public TessellationEngine {
 public:
  // `note`: why the CPU was chosen, when it was not asked for (appended to detail()).
  explicit CpuTessellationEngine(PatchSetCache& patches, std::string note = {})
      : patches_(patches), note_(std::move(note)) {}
  std::string name() const override { return "cpu"; }
  bool available() const override { return true; }
  std::string detail() const override;
  TessellationOutput run(const ControlMesh& mesh, const TessellationJob& job,
                         const CancellationToken& cancel) override;
  bool preprocessed(const std::string& meshSha256, double finestRelativeTolerance) const override {
    return patches_.holds(meshSha256, finestRelativeTolerance);
  }

 protected:
  // Where a job's vertices are evaluated, given its patch set: null for the CPU's own path.
  using VertexEvaluationFor =
      std::function<std::unique_ptr<VertexEvaluation>(const std::shared_ptr<const PatchSet>&, const TessellationJob&)>;
  // The job, its vertices evaluated by `device` (may be empty).
  TessellationOutput runWith(const ControlMesh& mesh, const TessellationJob& job, const CancellationToken& cancel,
                             const VertexEvaluationFor& device);

 private:
  PatchSetCache& patches_;
  std::string note_;
};

}  // namespace tessera::server
