#include "server/tessellation/cpu_engine.h"

#include <chrono>
#include <string>

#include "core/pipeline/glb_output.h"
#include "core/pipeline/memory_estimates.h"
#include "core/pipeline/preprocessing.h"
#include "core/pipeline/tessellate.h"

namespace tessera::server {

namespace {

// `uvs`: the mesh has UVs, whose evaluation and seam copies the output's memory includes.
TessellationOptions optionsFor(const TessellationJob& job, const CancellationToken& cancel, bool uvs) {
  TessellationOptions options;
  options.accuracy = job.accuracy;
  options.camera = job.camera;
  options.eta = job.eta;
  if (job.maxTriangles > 0) options.maxTriangles = job.maxTriangles;
  options.checkpoint = [&cancel] { cancel.throwIfCancelled(); };
  if (job.memory) {
    // The output's memory, reserved once the plan knows its triangles (and set again if
    // planning goes round again).
    options.beforeOutput = [memory = job.memory, uvs, held = int64_t(0)](int64_t triangles) mutable {
      memory->hold(held, tessellationBytes(triangles, uvs), "the output (" + std::to_string(triangles) + " triangles)");
    };
  }
  return options;
}

}  // namespace

std::string CpuTessellationEngine::detail() const {
  const std::string detail = "EBOAT on the CPU: OpenSubdiv Far preprocessing, CER FAS, watertight triangulation";
  return note_.empty() ? detail : detail + " (" + note_ + ")";
}

TessellationOutput CpuTessellationEngine::run(const ControlMesh& mesh, const TessellationJob& job,
                                              const CancellationToken& cancel) {
  return runWith(mesh, job, cancel, {});
}

TessellationOutput CpuTessellationEngine::runWith(const ControlMesh& mesh, const TessellationJob& job,
                                                  const CancellationToken& cancel, const VertexEvaluationFor& device) {
  using Clock = std::chrono::steady_clock;
  auto seconds = [](Clock::time_point since) { return std::chrono::duration<double>(Clock::now() - since).count(); };
  auto progress = [&](const char* stage, double fraction) {
    if (job.reportProgress) job.reportProgress(stage, fraction);
  };
  TessellationOutput output;
  auto start = Clock::now();
  progress("preprocessing", 0.0);
  TessellationOptions options = optionsFor(job, cancel, mesh.hasUvs());
  std::shared_ptr<const PatchSet> patches =
      patches_.get(mesh, job.meshSha256, cancel, job.memory, finestRelativeTolerance(mesh, options));
  output.summary.timings.push_back({"preprocess", seconds(start)});
  cancel.throwIfCancelled();

  progress("tessellating", 0.3);
  start = Clock::now();
  const std::unique_ptr<VertexEvaluation> evaluation = device ? device(patches, job) : nullptr;
  options.vertexEvaluation = evaluation.get();
  const std::optional<PositionQuantization> positions = reserveForEncoding(job.encoding, *patches, options);
  TessellationResult result = tessellate(*patches, mesh, options);
  output.summary.timings.push_back({"tessellate", seconds(start)});
  cancel.throwIfCancelled();

  progress("encoding", 0.9);
  start = Clock::now();
  output.glb = writeGlb(result.mesh, glbOptionsFor({job.encoding, job.meshId, job.meshSha256}, options,
                                                   result.summary, positions));
  output.summary.timings.push_back({"encode", seconds(start)});
  const tessera::TessellationSummary& s = result.summary;
  output.summary.triangles = s.triangles;
  output.summary.patches = s.pieces;
  output.summary.rings = s.rings;
  output.summary.averageDepth = s.averageDepth;
  output.summary.maxDepth = s.maxDepth;
  output.summary.guaranteedBound = s.guaranteedBound;
  output.summary.tolerance = s.tolerance;  // what was used: in pixel mode the smallest piece's ε
  progress("done", 1.0);
  return output;
}

}  // namespace tessera::server
