// CER-based FAS on the GPU, one warp per extraordinary ring (paper §4.2 and §4.2.1): the ring
// is loaded once, refined level by level in a ring buffer in shared memory, and every level's
// refined set (12n+1 points) is written once to device memory. The per-lane work is
// gpu/cuda/warp_fas.h, shared with the CPU-side warp simulation; the rules are core/rings/fas_rules.h,
// decoded once per batch (warp_step_program.h).
//
// Built with --fmad=false (see CMakeLists.txt): with no contraction, the same operations in the
// same order round as core/rings/fas.cpp (-ffp-contract=off) does, so results match the CPU bit for bit.
#include "gpu/cuda/cuda_runtime_support.h"
#include "gpu/cuda/fas_launch.h"

namespace tessera::cuda::detail {
namespace {

// kSharedBuffers is a template parameter so that, on the main path, the buffer pointer is known
// to be shared memory and the compiler emits shared loads and stores rather than generic ones.
// Minimum resident blocks, chosen from ptxas reports (sm_90, nvcc 13.0), not yet from timings:
// the shared variant fits 8 blocks (64 warps, 32 registers) without spills; the global-scratch
// variant spills at 32 registers and takes 6 blocks (40 registers, no spills).
template <bool kSharedBuffers>
__global__ void __launch_bounds__(kMaxWarpsPerBlock* kWarpSize, kSharedBuffers ? 8 : 6)
    warpFasKernel(WarpFasPlan plan, WarpStepProgram step, int count,
                  const float* __restrict__ rings, float* __restrict__ output,
                  float* __restrict__ scratch) {
  extern __shared__ float4 shared[];  // float4: 16-byte alignment for the layout in warp_fas.h

  const int lane = int(threadIdx.x) % kWarpSize;
  const int warp = int(threadIdx.x) / kWarpSize;
  const WarpFasLayout& layout = plan.layout;
  float* buffer = kSharedBuffers ? plan.sharedWarpBuffer(shared, warp)
                                 : plan.scratchWarpBuffer(scratch, int(blockIdx.x), warp);
  // The loop bound is the same for all lanes of a warp, so the full-mask __syncwarp()s are legal.
  for (int ring = plan.firstRing(int(blockIdx.x), warp); ring < count;
       ring += plan.ringStride(int(gridDim.x))) {
    warpLoadRing(layout, lane, rings + layout.inputOffset(ring), buffer);
    __syncwarp();
    for (int level = 0; level < layout.depth; ++level) {
      warpFacePass(step, layout, lane, buffer);
      __syncwarp();
      warpEdgeVertexPass(step, layout, lane, buffer);
      __syncwarp();
      warpStoreLevel(layout, lane, buffer, output + layout.outputOffset(ring, level));
      __syncwarp();
    }
  }
}

void check(cudaError_t status, const char* what) { checkCuda(status, "CUDA FAS", what); }

template <bool kSharedBuffers>
int residentBlocksOf(const WarpFasPlan& plan) {
  int device = 0, multiprocessors = 0, perMultiprocessor = 0;
  check(cudaGetDevice(&device), "cudaGetDevice");
  check(cudaDeviceGetAttribute(&multiprocessors, cudaDevAttrMultiProcessorCount, device),
        "cudaDeviceGetAttribute(multiprocessors)");
  check(cudaOccupancyMaxActiveBlocksPerMultiprocessor(
            &perMultiprocessor, warpFasKernel<kSharedBuffers>, plan.warpsPerBlock * kWarpSize,
            plan.sharedBytes()),
        "cudaOccupancyMaxActiveBlocksPerMultiprocessor");
  int blocks = multiprocessors * perMultiprocessor;
  return blocks > 0 ? blocks : 1;
}

}  // namespace

int residentBlocks(const WarpFasPlan& plan) {
  return plan.sharedBuffers ? residentBlocksOf<true>(plan) : residentBlocksOf<false>(plan);
}

void launchWarpFas(const WarpFasPlan& plan, const WarpStepProgram& deviceStep, int count,
                   const float* rings, float* output, float* scratch, int blocks,
                   cudaStream_t stream) {
  if (count <= 0) return;
  const dim3 grid{unsigned(blocks)}, block{unsigned(plan.warpsPerBlock * kWarpSize)};
  if (plan.sharedBuffers) {
    warpFasKernel<true><<<grid, block, plan.sharedBytes(), stream>>>(plan, deviceStep, count,
                                                                     rings, output, scratch);
  } else {
    warpFasKernel<false><<<grid, block, plan.sharedBytes(), stream>>>(plan, deviceStep, count,
                                                                      rings, output, scratch);
  }
  check(cudaGetLastError(), "warpFasKernel launch");
}

}  // namespace tessera::cuda::detail
