// A patch set's surface tree in the flat arrays the vertex kernel reads (gpu/cuda/vertex_threads.h),
// in host memory: what CudaSurface copies to the device once, and what the simulation tests read
// in place. Plain C++: no CUDA types.
#pragma once

#include <vector>

#include "core/rings/patch_set.h"
#include "core/surface/surface_tree.h"
#include "gpu/cuda/vertex_threads.h"

namespace tessera::cuda {

struct SurfaceUpload {
  std::vector<SurfaceNode> nodes;
  std::vector<EvBottom> evBottoms;
  std::vector<Vec3> regularNets;  // 16 per regular patch
  std::vector<Vec3> fasNets;      // 16 per FAS leaf, relative to its ring's centre
  std::vector<Vec3> fasCenters;   // per FAS leaf

  size_t bytes() const;
  // The view of these arrays where they are (the simulation's host view).
  SurfaceView view() const;
};

// Requires patches.adaptive (every patch set buildPatchSet makes has it).
SurfaceUpload makeSurfaceUpload(const PatchSet& patches);

}  // namespace tessera::cuda
