// CER-based FAS on a CUDA device (paper §4.2), one warp per extraordinary ring; the GPU
// counterpart of core/rings/fas.h. Plain C++: no CUDA type appears here, so server and CLI code call
// it with g++ alone.
//
// Output layout is refineRing's, ring after ring: for ring r, level l (0-based), point p,
// coordinate c the float at ((r·depth + l)·refinedPointCount + p)·3 + c.
//
// Limits: depth 1..24; valence (sectors) ≥ 2 closed, ≥ 1 open. Rings of valence ≤ 64 are
// refined in shared memory; larger valences are refined by the same kernel in a global-memory
// scratch buffer (slower, still exact). Bad input throws TesseraError before any CUDA call;
// no device throws TesseraError(kUnsupported, "no CUDA device: ..."); a failing CUDA call
// throws std::runtime_error naming the call and the CUDA error.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "core/rings/fas_rules.h"

namespace tessera::cuda {

// A batch of smooth, closed rings of one valence.
struct CudaRingBatch {
  int valence = 0;
  int depth = 0;
  int count = 0;
};

// Floats the output of `count` rings refined to `depth` takes.
size_t cudaFasOutputFloats(const cer::RingShape& shape, int depth, int count);

// Throws TesseraError naming the first problem; touches no CUDA state.
void validateCudaFasInput(const RingRules& rules, int depth, int count, const void* rings);

// Host arrays in and out: `rings` holds batch.count rings, ringPointCount × xyz each. Uploads,
// runs, waits and downloads.
std::vector<float> refineRingsCuda(const CudaRingBatch& batch, const float* rings);
// Any ring kind fas_rules.h supports (sharp spokes, open rings, crease/corner EV).
std::vector<float> refineRingsCuda(const RingRules& rules, int depth, int count,
                                   const float* rings);

// Device-resident batch for benchmarks and for GPU consumers of the refined points: the rings
// are uploaded once in the constructor, launch() only enqueues the kernel.
class CudaFasBatch {
 public:
  CudaFasBatch(const RingRules& rules, int depth, int count, const float* hostRings);
  ~CudaFasBatch();
  CudaFasBatch(const CudaFasBatch&) = delete;
  CudaFasBatch& operator=(const CudaFasBatch&) = delete;

  void launch();  // asynchronous, on the batch's own stream
  // Mean milliseconds per launch over `repetitions` back-to-back launches, measured with CUDA
  // events around the kernels alone (no transfers).
  float timeKernelMs(int repetitions);
  std::vector<float> download();  // waits for the stream, then copies the output to the host

  const float* deviceRings() const;
  float* deviceOutput() const;
  size_t outputFloats() const;
  int blocks() const;  // grid size used (resident blocks, grid-stride over the rings)
  int warpsPerBlock() const;
  bool sharedBuffers() const;  // false: valence > 64, ring buffers in global scratch

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tessera::cuda
