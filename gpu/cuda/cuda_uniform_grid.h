// The uniform grid (core/uniform/uniform_grid.h, the paper's Table 2) evaluated on a CUDA device: the
// pieces planUniformGrid chose, sampled from their nets straight into device memory, equal bit for
// bit to evaluateUniformGrid on the CPU (core/math/grid_sample.h is both sides' arithmetic). Planning
// (CER FAS of the rings, the ring nets) stays on the CPU. Plain C++: no CUDA types.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/uniform/uniform_grid.h"
#include "gpu/cuda/grid_threads.h"

namespace tessera::cuda {

// The grid as the device reads it (gpu/cuda/grid_threads.h's GridView), in host memory: every
// piece's net (regular patches' then the ring nets), its record, the weight tables and the sample
// offsets.
struct GridUpload {
  std::vector<Vec3> nets;
  std::vector<GridPieceRecord> pieces;
  std::vector<ParameterWeights> weights;
  std::vector<uint64_t> offsets;
};
GridUpload makeGridUpload(const PatchSet& patches, const UniformGrid& grid);

// Device-resident grid: uploaded once in the constructor; launch() only enqueues the kernel.
// No device throws TesseraError(kUnsupported, "no CUDA device: ..."); a failing CUDA call throws
// std::runtime_error naming it.
class CudaUniformGrid {
 public:
  CudaUniformGrid(const PatchSet& patches, const UniformGrid& grid);
  ~CudaUniformGrid();
  CudaUniformGrid(const CudaUniformGrid&) = delete;
  CudaUniformGrid& operator=(const CudaUniformGrid&) = delete;

  void launch();  // asynchronous, on the grid's own stream
  // Mean milliseconds per launch over `repetitions` back-to-back launches (CUDA events around
  // the kernels alone).
  float timeKernelMs(int repetitions);
  std::vector<Vec3> download();  // waits for the stream, then copies the samples to the host

  size_t samples() const;
  const Vec3* deviceSamples() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tessera::cuda
