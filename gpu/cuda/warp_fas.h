// Warp-per-ring CER FAS (paper §4.2): what each lane of a warp does between two __syncwarp()s,
// written once as host-device code so that the CUDA kernel (fas_kernel.cu) and the CPU-side
// warp simulation (tests/cuda/warp_fas_simulation_test.cpp) run the very same indexing.
//
// One warp owns one extraordinary ring at a time. Its ring buffer has two halves: the current
// ring (6n+1 points) and the refined set (12n+1 points), xyz floats per point (W = 3 in
// fas_rules.h). A level is three phases:
//   1. face points, one sector per lane                                  (refineSectorFaces)
//   2. spoke edges/vertices and sector interiors, one per lane, and the EV on lane 0
//   3. the refined set streamed to device memory by all lanes, its prefix (the next ring)
//      copied back into the ring half in the same pass.
// After the last level the ring half holds the innermost ring.
//
// Plain C++ apart from TESSERA_HD: no CUDA types, so g++ compiles it for the simulation.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/fas_rules.h"
#include "core/host_device.h"

namespace tessera::cuda {

inline constexpr int kWarpSize = 32;
// Rings up to this valence keep their ring buffer in shared memory; larger ones use a slice of
// a global-memory scratch array (same code, another base pointer).
inline constexpr int kMaxSharedValence = 64;
inline constexpr int kMaxCudaFasDepth = 24;
inline constexpr int kMaxWarpsPerBlock = 8;
// Shared memory a block may use without cudaFuncSetAttribute opt-in.
inline constexpr int kSharedBytesPerBlock = 48 * 1024;

// Float offsets of one warp's ring buffer and of the per-ring output.
struct WarpFasLayout {
  int ringFloats = 0;     // 3 × ringPointCount: the ring half, at the start of the buffer
  int refinedFloats = 0;  // 3 × refinedPointCount: the refined half, right after it
  int depth = 0;

  TESSERA_HD int bufferFloats() const { return ringFloats + refinedFloats; }
  // Input: rings one after another, xyz per point.
  TESSERA_HD size_t inputOffset(int ring) const { return size_t(ring) * size_t(ringFloats); }
  // Output in refineRing's per-ring layout: ring after ring, each its levels one after another.
  TESSERA_HD size_t outputOffset(int ring, int level) const {
    return (size_t(ring) * size_t(depth) + size_t(level)) * size_t(refinedFloats);
  }
};

TESSERA_HD WarpFasLayout makeWarpFasLayout(const cer::RingShape& shape, int depth) {
  WarpFasLayout layout;
  layout.ringFloats = 3 * shape.ringPointCount();
  layout.refinedFloats = 3 * shape.refinedPointCount();
  layout.depth = depth;
  return layout;
}

// How a launch spreads rings over warps and where each warp's buffer lives. Shared memory holds
// the sharp-spoke flags first (rounded up to 16 bytes), then one ring buffer per warp.
struct WarpFasPlan {
  WarpFasLayout layout;
  int warpsPerBlock = 0;
  int flagBytes = 0;
  bool sharedBuffers = true;  // false: ring buffers in global scratch (valence > 64)

  TESSERA_HD size_t bufferBytes() const { return size_t(layout.bufferFloats()) * sizeof(float); }
  TESSERA_HD size_t sharedBytes() const {
    return size_t(flagBytes) + (sharedBuffers ? size_t(warpsPerBlock) * bufferBytes() : 0);
  }
  // Scratch floats a grid of `blocks` needs when the buffers are global.
  TESSERA_HD size_t scratchFloats(int blocks) const {
    return sharedBuffers ? 0
                         : size_t(blocks) * size_t(warpsPerBlock) * size_t(layout.bufferFloats());
  }
  TESSERA_HD uint8_t* sharedFlags(void* shared) const { return static_cast<uint8_t*>(shared); }
  TESSERA_HD float* sharedWarpBuffer(void* shared, int warp) const {
    return reinterpret_cast<float*>(static_cast<uint8_t*>(shared) + flagBytes) +
           size_t(warp) * size_t(layout.bufferFloats());
  }
  TESSERA_HD float* scratchWarpBuffer(float* scratch, int block, int warp) const {
    return scratch +
           (size_t(block) * size_t(warpsPerBlock) + size_t(warp)) * size_t(layout.bufferFloats());
  }
  // Grid-stride assignment: warp w of block b takes rings b·warps + w, then every grid·warps.
  TESSERA_HD int firstRing(int block, int warp) const { return block * warpsPerBlock + warp; }
  TESSERA_HD int ringStride(int blocks) const { return blocks * warpsPerBlock; }
};

// Host side: as many warps per block (up to 8) as fit in 48 KB of shared memory.
inline WarpFasPlan planWarpFas(const cer::RingShape& shape, int depth) {
  WarpFasPlan plan;
  plan.layout = makeWarpFasLayout(shape, depth);
  plan.flagBytes = (shape.spokeCount() + 15) / 16 * 16;
  plan.sharedBuffers = shape.sectors <= kMaxSharedValence;
  plan.warpsPerBlock = kMaxWarpsPerBlock;
  if (plan.sharedBuffers) {
    int fit = int((kSharedBytesPerBlock - plan.flagBytes) / plan.bufferBytes());
    plan.warpsPerBlock = fit < kMaxWarpsPerBlock ? fit : kMaxWarpsPerBlock;
  }
  return plan;
}

// Block-wide, before the warps start: copy the sharp-spoke flags next to the ring buffers, so
// that refineSpoke reads them from shared memory. Returns the rules the warps use.
TESSERA_HD RingRules stageSharpSpokes(const RingRules& rules, uint8_t* sharedFlags, int thread,
                                      int threads) {
  RingRules staged = rules;
  if (rules.sharpSpokes == nullptr) return staged;
  for (int s = thread; s < rules.shape.spokeCount(); s += threads) {
    sharedFlags[s] = rules.sharpSpokes[s];
  }
  staged.sharpSpokes = sharedFlags;
  return staged;
}

// Phase 0: the ring's 6n+1 points into the ring half; consecutive lanes read consecutive floats.
TESSERA_HD void warpLoadRing(const WarpFasLayout& layout, int lane, const float* ring,
                             float* buffer) {
  for (int f = lane; f < layout.ringFloats; f += kWarpSize) buffer[f] = ring[f];
}

// Phase 1: the four face points of each sector (needed by every rule of phase 2).
TESSERA_HD void warpFacePass(const RingRules& rules, const WarpFasLayout& layout, int lane,
                             float* buffer) {
  const float* ring = buffer;
  float* refined = buffer + layout.ringFloats;
  for (int i = lane; i < rules.shape.sectors; i += kWarpSize) {
    refineSectorFaces<3>(rules, i, ring, refined);
  }
}

// Phase 2: edge and vertex points. Spokes, sector interiors and the EV write disjoint points and
// read only the ring and phase-1 face points, so they share one phase.
TESSERA_HD void warpEdgeVertexPass(const RingRules& rules, const WarpFasLayout& layout, int lane,
                                   float* buffer) {
  const float* ring = buffer;
  float* refined = buffer + layout.ringFloats;
  for (int j = lane; j < rules.shape.spokeCount(); j += kWarpSize) {
    refineSpoke<3>(rules, j, ring, refined);
  }
  for (int i = lane; i < rules.shape.sectors; i += kWarpSize) {
    refineSectorInterior<3>(rules, i, ring, refined);
  }
  // Sums the n sectors in the CPU path's order, which keeps the result bit-identical to it.
  if (lane == 0) refineExtraordinaryVertex<3>(rules, ring, refined);
}

// Phase 3: the refined set to device memory (written once, coalesced) and its first 6n+1 points
// back into the ring half as the next level's ring (paper §4.2: the head advances by 6n+1).
TESSERA_HD void warpStoreLevel(const WarpFasLayout& layout, int lane, float* buffer,
                               float* output) {
  const float* refined = buffer + layout.ringFloats;
  for (int f = lane; f < layout.refinedFloats; f += kWarpSize) {
    float value = refined[f];
    output[f] = value;
    if (f < layout.ringFloats) buffer[f] = value;
  }
}

}  // namespace tessera::cuda
