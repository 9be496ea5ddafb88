// What a tessellation request asks for: a tolerance (absolute, relative to the bounding-box
// diagonal, or pixel accuracy for a camera), the η split, or a uniform level for benchmarks.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>

#include "core/vec3.h"

namespace tessera {

struct Camera {
  Vec3d eye, target, up{0, 1, 0};
  double fovYDegrees = 45;
  int width = 1920, height = 1080;
};

struct TessellationOptions {
  double tolerance = 1e-3;        // absolute, or a fraction of the diagonal when relative
  bool relativeTolerance = false;
  std::optional<Camera> camera;   // makes the tolerance pixel-accurate for this view
  double pixelAccuracy = 0.5;     // in pixels, with a camera
  // Share of ε for the Bézier approximation (paper §5.1), in [0, 1). 0 is the paper's
  // single-phase baseline: innermost quads become triangle pairs and the depth alone meets ε.
  double eta = 0.5;
  int uniformLevel = 0;           // > 0: the paper's Table 2 setup instead of a tolerance
  int64_t maxTriangles = 20'000'000;
  // Model units of ε set aside for the output's encoding (quantized positions move each vertex by
  // at most this much, core/glb_output.h): the surface is planned to ε minus it everywhere and
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
};

// Throws TesseraError (kInvalidInput) naming the bad field: zero, negative or non-finite
// tolerance, η outside [0, 1), a degenerate camera, a non-positive viewport, a level outside
// 1..4096.
void validateTessellationOptions(const TessellationOptions& options);

// Throws TesseraError (kInvalidInput) unless 1 <= p <= kMaxUniformLevel.
void validateUniformLevel(int p);

}  // namespace tessera
