// The adaptive tessellation's vertices on the GPU: one thread per vertex, the per-thread work in
// gpu/cuda/vertex_threads.h. Built with --fmad=false, so the vertices equal the CPU engine's bit
// for bit (core/surface/surface_point.h is both sides' arithmetic).
#include "gpu/cuda/cuda_runtime_support.h"
#include "gpu/cuda/vertex_launch.h"

namespace tessera::cuda::detail {
namespace {

__global__ void __launch_bounds__(kVerticesPerBlock) vertexKernel(VertexView view) {
  const uint64_t i = uint64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i < view.count) evaluateVertex(view, i);
}

}  // namespace

void launchVertices(const VertexView& view, cudaStream_t stream) {
  if (view.count == 0) return;
  const auto blocks = unsigned((view.count + kVerticesPerBlock - 1) / kVerticesPerBlock);
  vertexKernel<<<dim3(blocks), dim3(kVerticesPerBlock), 0, stream>>>(view);
  checkCuda(cudaGetLastError(), "CUDA vertices", "vertexKernel launch");
}

}  // namespace tessera::cuda::detail
