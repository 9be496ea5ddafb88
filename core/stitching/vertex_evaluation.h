// Where the adaptive tessellation's vertices are put on the limit surface. By default on the
// CPU, each run of roots just before its tiles are triangulated, from that core's cache
// (core/stitching/adaptive_tessellator.cpp); an engine with a device (gpu/cuda) evaluates them all there at
// once with the same arithmetic (core/surface/surface_point.h) and hands back the same values.
#pragma once

#include <vector>

#include "core/adaptive/adaptive_plan.h"
#include "core/base/vec3.h"
#include "core/stitching/tile_stitching.h"

namespace tessera {

class VertexEvaluation {
 public:
  virtual ~VertexEvaluation() = default;
  // Every vertex the stitching asks for (stitching.vertices[i], in the root of plan tile
  // vertices[i].tile, from that tile's node) into positions[i] and its unit normal into
  // normals[i]; both already sized. Copies (i ≥ stitching.copyFirst) are evaluated like the
  // others: the caller gives them their original's position afterwards. False when it could not
  // (a device out of memory): the CPU evaluates them then, as without it.
  virtual bool evaluate(const AdaptivePlan& plan, const Stitching& stitching, std::vector<Vec3>& positions,
                        std::vector<Vec3>& normals) = 0;
};

}  // namespace tessera
