// Warp-per-ring CER FAS (paper §4.2): what each lane of a warp does between two __syncwarp()s,
// written once as host-device code so that the CUDA kernel (fas_kernel.cu) and the CPU-side
// warp simulation (tests/cuda/warp_fas_simulation_test.cpp) run the very same indexing.
//
// One warp owns one extraordinary ring at a time. Its ring buffer has two halves: the current
// ring (6n+1 points) and the refined set (12n+1 points), xyz floats per point (W = 3 in
// fas_rules.h). The step's rules come decoded (warp_step_program.h), so the lanes stride over
// records rather than sectors. A level is three phases:
//   1. the 4n face points, lane k taking records k, k+32, …          (refineSectorFaces)
//   2. edge and vertex points likewise, and the EV on lanes 0–2, one coordinate each
//   3. the refined set streamed to device memory by all lanes, its prefix (the next ring)
//      copied back into the ring half in the same pass.
// After the last level the ring half holds the innermost ring.
//
// Plain C++ apart from TESSERA_HD: no CUDA types, so g++ compiles it for the simulation.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/base/host_device.h"
#include "core/rings/fas_rules.h"
#include "gpu/cuda/warp_step_program.h"

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

// How a launch spreads rings over warps and where each warp's buffer lives: shared memory holds
// one ring buffer per warp.
struct WarpFasPlan {
  WarpFasLayout layout;
  int warpsPerBlock = 0;
  bool sharedBuffers = true;  // false: ring buffers in global scratch (valence > 64)

  TESSERA_HD size_t bufferBytes() const { return size_t(layout.bufferFloats()) * sizeof(float); }
  TESSERA_HD size_t sharedBytes() const {
    return sharedBuffers ? size_t(warpsPerBlock) * bufferBytes() : 0;
  }
  // Scratch floats a grid of `blocks` needs when the buffers are global.
  TESSERA_HD size_t scratchFloats(int blocks) const {
    return sharedBuffers ? 0
                         : size_t(blocks) * size_t(warpsPerBlock) * size_t(layout.bufferFloats());
  }
  TESSERA_HD float* sharedWarpBuffer(void* shared, int warp) const {
    return static_cast<float*>(shared) + size_t(warp) * size_t(layout.bufferFloats());
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
  plan.sharedBuffers = shape.sectors <= kMaxSharedValence;
  plan.warpsPerBlock = kMaxWarpsPerBlock;
  if (plan.sharedBuffers) {
    int fit = int(kSharedBytesPerBlock / plan.bufferBytes());
    plan.warpsPerBlock = fit < kMaxWarpsPerBlock ? fit : kMaxWarpsPerBlock;
  }
  return plan;
}

// Phase 0: the ring's 6n+1 points into the ring half; consecutive lanes read consecutive floats.
TESSERA_HD void warpLoadRing(const WarpFasLayout& layout, int lane, const float* ring,
                             float* buffer) {
  for (int f = lane; f < layout.ringFloats; f += kWarpSize) buffer[f] = ring[f];
}

// Phase 1: the face points (needed by every rule of phase 2).
TESSERA_HD void warpFacePass(const WarpStepProgram& step, const WarpFasLayout& layout, int lane,
                             float* buffer) {
  const float* in = buffer;
  float* out = buffer + layout.ringFloats;
  for (int k = lane; k < step.faceCount; k += kWarpSize) {
    const StepProgram::Face& f = step.faces[k];
    fas_detail::average4<3, float>(out + f.out, in + f.a, in + f.b, in + f.c, in + f.d);
  }
}

// Phase 2, the EV: lane k < 3 computes coordinate k, summing the sectors in refineRing's order
// (refineExtraordinaryVertex), which keeps the result bit-identical to it.
TESSERA_HD void warpExtraordinaryVertex(const WarpStepProgram& step, int k, const float* in,
                                        float* out) {
  if (step.evRule == EvRule::kCorner) {
    out[k] = in[k];
  } else if (step.evRule == EvRule::kCrease) {
    fas_detail::creaseVertex<1, float>(out + k, in + k, in + step.evCreaseA + k,
                                       in + step.evCreaseB + k);
  } else {
    float sum = 0;
    for (int i = 0; i < step.evTermCount; ++i) {
      sum += in[step.evTerms[i].edge + k] + out[step.evTerms[i].face + k];
    }
    out[k] = step.evSelfWeight * in[k] + step.evRingWeight * sum;
  }
}

// Phase 2: edge and vertex points. They write disjoint points and read only the ring and
// phase-1 face points, so they share one phase.
TESSERA_HD void warpEdgeVertexPass(const WarpStepProgram& step, const WarpFasLayout& layout,
                                   int lane, float* buffer) {
  using namespace fas_detail;
  const float* in = buffer;
  float* out = buffer + layout.ringFloats;
  for (int k = lane; k < step.smoothEdgeCount; k += kWarpSize) {
    const StepProgram::SmoothEdge& e = step.smoothEdges[k];
    average4<3, float>(out + e.out, in + e.v0, in + e.v1, out + e.f0, out + e.f1);
  }
  for (int k = lane; k < step.sharpEdgeCount; k += kWarpSize) {
    const StepProgram::SharpEdge& e = step.sharpEdges[k];
    midpoint<3, float>(out + e.out, in + e.v0, in + e.v1);
  }
  for (int k = lane; k < step.smoothVertexCount; k += kWarpSize) {
    const StepProgram::SmoothVertex& v = step.smoothVertices[k];
    const float* const neighbours[4] = {in + v.n[0], in + v.n[1], in + v.n[2], in + v.n[3]};
    const float* const faces[4] = {out + v.f[0], out + v.f[1], out + v.f[2], out + v.f[3]};
    regularVertex<3, float>(out + v.out, in + v.v, neighbours, faces);
  }
  for (int k = lane; k < step.creaseVertexCount; k += kWarpSize) {
    const StepProgram::CreaseVertex& v = step.creaseVertices[k];
    creaseVertex<3, float>(out + v.out, in + v.v, in + v.n0, in + v.n1);
  }
  if (lane < 3) warpExtraordinaryVertex(step, lane, in, out);
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
