// What a tessellation request asks for: an accuracy (core/request/accuracy.h) with its camera when it
// is pixel-accurate, the η split, budgets and the caller's hooks.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>

#include "core/request/accuracy.h"
#include "core/request/camera.h"

namespace tessera {

class VertexEvaluation;  // core/stitching/vertex_evaluation.h

struct TessellationOptions {
  Accuracy accuracy;
  std::optional<Camera> camera;   // the view a pixel accuracy is for; only with Mode::kPixel
  // Share of ε for the Bézier approximation (paper §5.1), in [0, 1). 0 is the paper's
  // single-phase baseline: innermost quads become triangle pairs and the depth alone meets ε.
  double eta = 0.5;
  int64_t maxTriangles = 20'000'000;
  // Model units of ε set aside for the output's encoding (quantized positions move each vertex by
  // at most this much, core/pipeline/glb_output.h): the surface is planned to ε minus it everywhere and
  // the bound reported includes it.
  double encodingReserve = 0;
  bool recordParameters = false;  // keep each triangle's piece coordinates (tests, tools)
  // Called every few hundred rings or pieces during long work; a caller that wants to stop
  // (a cancelled or expired request) throws from it, and the exception leaves tessellate().
  std::function<void()> checkpoint;
  // Called with the triangle count a plan will make (after the maxTriangles check), before the
  // output is built from it; may throw. A server reserves the output's memory here. Called again
  // if planning has to go round again.
  std::function<void(int64_t triangles)> beforeOutput;
  // Where a tolerance request's vertices are evaluated (core/stitching/vertex_evaluation.h); null: on the
  // CPU. Not owned.
  VertexEvaluation* vertexEvaluation = nullptr;
};

// Throws TesseraError (kInvalidInput) naming the bad field: the accuracy (validateAccuracy), a
// pixel accuracy without its camera or a camera without a pixel accuracy, the camera
// (validateCamera), η outside [0, 1), a non-positive triangle budget or a negative reserve.
void validateTessellationOptions(const TessellationOptions& options);

}  // namespace tessera
