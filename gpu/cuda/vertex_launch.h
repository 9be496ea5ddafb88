// Internal to gpu/cuda: the launch of the vertex kernel (vertex_kernel.cu) as seen by the host
// API (cuda_surface.cpp).
#pragma once

#include <cuda_runtime_api.h>

#include "gpu/cuda/vertex_threads.h"

namespace tessera::cuda::detail {

inline constexpr unsigned kVerticesPerBlock = 128;

// Enqueues, on `stream`, one thread per vertex of `view` (device pointers).
void launchVertices(const VertexView& view, cudaStream_t stream);

}  // namespace tessera::cuda::detail
