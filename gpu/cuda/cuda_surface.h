// The adaptive tessellation's vertices on a CUDA device: a patch set's surface tree uploaded once
// (CudaSurface, what the CUDA engine caches per mesh), and per request the stitching's vertex
// requests and its tiles' nodes copied up, one thread per vertex (vertex_kernel.cu), positions and
// normals copied down (CudaVertexEvaluation). Planning, stitching and triangulation stay on the
// CPU. Equal bit for bit to the CPU's evaluation (core/surface/surface_point.h). Plain C++: no CUDA types.
#pragma once

#include <memory>
#include <vector>

#include "core/rings/patch_set.h"
#include "core/stitching/vertex_evaluation.h"
#include "gpu/cuda/device_out_of_memory.h"
#include "gpu/cuda/vertex_threads.h"

namespace tessera::cuda {

// No device throws TesseraError(kUnsupported, "no CUDA device: ..."), a device out of memory
// DeviceOutOfMemory (gpu/cuda/device_out_of_memory.h); another failing CUDA call
// throws std::runtime_error naming it.
class CudaSurface {
 public:
  explicit CudaSurface(const PatchSet& patches);
  ~CudaSurface();
  CudaSurface(const CudaSurface&) = delete;
  CudaSurface& operator=(const CudaSurface&) = delete;

  size_t deviceBytes() const;
  // The arrays as the vertex kernel reads them (device pointers).
  const SurfaceView& deviceView() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One request's evaluation on `surface` (which must outlive it), on a stream of its own: any
// number may run at once. Throws like CudaSurface.
class CudaVertexEvaluation : public VertexEvaluation {
 public:
  explicit CudaVertexEvaluation(const CudaSurface& surface);
  ~CudaVertexEvaluation() override;

  // Always true: a device out of memory throws DeviceOutOfMemory (the caller decides).
  bool evaluate(const AdaptivePlan& plan, const Stitching& stitching, std::vector<Vec3>& positions,
                std::vector<Vec3>& normals) override;
  // Milliseconds the last evaluate() spent on the device (CUDA events around the kernel alone).
  float kernelMs() const { return kernelMs_; }

 private:
  const CudaSurface& surface_;
  float kernelMs_ = 0;
};

}  // namespace tessera::cuda
