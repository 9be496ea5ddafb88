#include "core/pipeline/glb_output.h"

#include <cstdio>

#include "core/base/error.h"
#include "core/surface/tolerance_model.h"

namespace tessera {

std::optional<PositionQuantization> reserveForEncoding(GlbEncoding encoding,
                                                       const PatchSet& patches,
                                                       TessellationOptions& options) {
  options.encodingReserve = 0;
  if (encoding == GlbEncoding::kFloat) return std::nullopt;
  const PositionQuantization grid = quantizationForBox(patches.boundsMin, patches.boundsMax);
  if (options.accuracy.uniform()) {
    options.encodingReserve = grid.maxError;
    return grid;
  }
  // The smallest ε anywhere: the one value, or with a camera the box's nearest corner (every part
  // of the surface lies in the control points' box, so none is nearer).
  const ToleranceModel tolerance(options, patches);
  const float lo[3] = {patches.boundsMin.x, patches.boundsMin.y, patches.boundsMin.z};
  const float hi[3] = {patches.boundsMax.x, patches.boundsMax.y, patches.boundsMax.z};
  const double smallest = tolerance.forBox(lo, hi);
  if (grid.maxError <= kQuantizationShare * smallest) {
    options.encodingReserve = grid.maxError;
    return grid;
  }
  if (encoding == GlbEncoding::kQuantized) {
    char message[256];
    std::snprintf(message, sizeof message,
                  "quantized positions move vertices by up to %.3g (16 bits over the mesh's box), "
                  "more than %g of "
                  "the smallest tolerance asked, %.3g; ask for a larger tolerance or the float or "
                  "meshopt encoding",
                  grid.maxError, kQuantizationShare, smallest);
    throwInvalid(message);
  }
  return std::nullopt;
}

GlbOptions glbOptionsFor(const GlbRequest& request, const TessellationOptions& options,
                         const TessellationSummary& summary,
                         const std::optional<PositionQuantization>& positions) {
  GlbOptions glb;
  glb.encoding = request.encoding;
  glb.positions = positions;
  glb.checkpoint = options.checkpoint;
  GlbDescription& d = glb.description;
  d.sourceName = request.sourceName;
  d.sourceSha256 = request.sourceSha256;
  d.guaranteedBound = summary.guaranteedBound;
  if (options.accuracy.uniform()) {
    d.uniformLevel = options.accuracy.level;
  } else if (options.accuracy.pixelAccurate()) {
    d.pixelAccuracy = options.accuracy.pixels;
  } else {
    d.tolerance = summary.tolerance;
  }
  return glb;
}

}  // namespace tessera
