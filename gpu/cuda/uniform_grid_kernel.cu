// The uniform grid on the GPU (paper Table 2): the blocks' first pieces, then one thread per
// sample; the per-thread work is gpu/cuda/grid_threads.h. Built with --fmad=false like the FAS
// kernel, so the samples equal the CPU's evaluateUniformGrid bit for bit (core/math/grid_sample.h).
#include "gpu/cuda/cuda_runtime_support.h"
#include "gpu/cuda/grid_launch.h"

namespace tessera::cuda::detail {
namespace {

__global__ void __launch_bounds__(kGridSamplesPerBlock) markBlocksKernel(GridView view) {
  const uint64_t q = uint64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (q < view.pieceCount) markBlockFirstPiece(view, q);
}

__global__ void __launch_bounds__(kGridSamplesPerBlock) uniformGridKernel(GridView view) {
  const GridBlockRange range = gridBlockRange(view, blockIdx.x);
  const uint64_t sample = range.firstSample + threadIdx.x;
  if (sample < range.endSample) writeGridSample(view, range, sample);
}

}  // namespace

void launchUniformGrid(const GridView& view, cudaStream_t stream) {
  if (view.sampleCount == 0) return;
  const auto markBlocks =
      unsigned((view.pieceCount + kGridSamplesPerBlock - 1) / kGridSamplesPerBlock);
  markBlocksKernel<<<dim3(markBlocks), dim3(kGridSamplesPerBlock), 0, stream>>>(view);
  checkCuda(cudaGetLastError(), "CUDA uniform grid", "markBlocksKernel launch");
  uniformGridKernel<<<dim3(unsigned(view.blocks())), dim3(kGridSamplesPerBlock), 0, stream>>>(view);
  checkCuda(cudaGetLastError(), "CUDA uniform grid", "uniformGridKernel launch");
}

}  // namespace tessera::cuda::detail
