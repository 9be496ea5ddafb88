// Internal to gpu/cuda: the launch of the warp-per-ring FAS kernel (fas_kernel.cu) as seen by
// the host API (cuda_fas.cpp). Uses CUDA runtime types; callers outside gpu/cuda use cuda_fas.h.
#pragma once

#include <cuda_runtime_api.h>

#include "gpu/cuda/warp_fas.h"

namespace tessera::cuda::detail {

// Blocks of `plan` that stay resident on the current device at once (occupancy × SMs), at
// least 1. The launch uses min(this, blocks needed) and walks the rings grid-stride.
int residentBlocks(const WarpFasPlan& plan);

// Enqueues the kernel on `stream`. `deviceStep`'s records are in device memory;
// `scratch` holds plan.scratchFloats(blocks) floats when the plan's buffers are global.
void launchWarpFas(const WarpFasPlan& plan, const WarpStepProgram& deviceStep, int count,
                   const float* rings, float* output, float* scratch, int blocks,
                   cudaStream_t stream);

}  // namespace tessera::cuda::detail
