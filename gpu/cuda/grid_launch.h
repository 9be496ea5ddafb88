// Internal to gpu/cuda: the launch of the uniform-grid kernel (uniform_grid_kernel.cu) as seen by
// the host API (cuda_uniform_grid.cpp).
#pragma once

#include <cuda_runtime_api.h>

#include "gpu/cuda/grid_threads.h"

namespace tessera::cuda::detail {

// Enqueues, on `stream`, the marking of view.blockFirstPiece and one thread per sample of `view`
// (device pointers).
void launchUniformGrid(const GridView& view, cudaStream_t stream);

}  // namespace tessera::cuda::detail
