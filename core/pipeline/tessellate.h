// The whole tessellation pipeline for one request: plan (depths and levels), budget check,
// watertight triangulation, and the numbers a user wants back.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/mesh/control_mesh.h"
#include "core/request/tessellation_options.h"
#include "core/rings/patch_set.h"
#include "core/uniform/tessellation_plan.h"
#include "core/uniform/watertight_tessellator.h"

namespace tessera {

struct TessellationSummary {
  int64_t triangles = 0;
  int64_t vertices = 0;
  int64_t pieces = 0;
  int rings = 0;
  double averageDepth = 0;
  int maxDepth = 0;
  double guaranteedBound = 0;  // distance to the limit surface the output is proven to stay within
  double tolerance = 0;        // ε in object space (smallest per-piece ε in pixel mode; 0 for a uniform level)
  double planMs = 0, tessellateMs = 0;
};

struct TessellationResult {
  TriangleMesh mesh;
  TessellationPlan plan;  // the pieces the triangles belong to (TriangleMesh::trianglePiece)
  TessellationSummary summary;
};

// Throws TesseraError for bad options (checked once, by the planner the accuracy goes to:
// planRoots or planTessellation, before any work) and kLimitExceeded, before building
// anything, when the triangle budget would be passed.
TessellationResult tessellate(const PatchSet& patches, const ControlMesh& mesh,
                              const TessellationOptions& options);

}  // namespace tessera
