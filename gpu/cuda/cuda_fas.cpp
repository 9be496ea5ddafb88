// Host side of the CUDA FAS backend: input checks, device buffers, launches and timing.
// The kernel itself is fas_kernel.cu.
#include "gpu/cuda/cuda_fas.h"

#include <cuda_runtime_api.h>

#include <climits>
#include <string>

#include "core/base/error.h"
#include "gpu/cuda/cuda_runtime_support.h"
#include "gpu/cuda/fas_launch.h"

namespace tessera::cuda {
namespace {

void check(cudaError_t status, const char* what) { detail::checkCuda(status, "CUDA FAS", what); }

template <class T>
detail::DeviceArray<T> allocate(size_t count, const char* what) {
  return detail::allocateDevice<T>(count, "CUDA FAS", what);
}

}  // namespace

size_t cudaFasOutputFloats(const cer::RingShape& shape, int depth, int count) {
  return size_t(count) * size_t(depth) * size_t(shape.refinedPointCount()) * 3;
}

void validateCudaFasInput(const RingRules& rules, int depth, int count, const void* rings) {
  const cer::RingShape& shape = rules.shape;
  const int minimum = shape.open ? 1 : 2;
  if (shape.sectors < minimum) {
    throwInvalid("CUDA FAS: " +
                 std::string(shape.open ? "an open ring needs at least 1 face"
                                        : "a closed ring needs valence >= 2") +
                 ", got " + std::to_string(shape.sectors));
  }
  if (depth < 1) throwInvalid("CUDA FAS: depth must be at least 1, got " + std::to_string(depth));
  if (depth > kMaxCudaFasDepth) {
    throwLimit("CUDA FAS: depth " + std::to_string(depth) + " exceeds the limit of " +
               std::to_string(kMaxCudaFasDepth));
  }
  if (count < 0) {
    throwInvalid("CUDA FAS: ring count must not be negative, got " + std::to_string(count));
  }
  // Ring indices advance grid-stride in int; keep them far from overflow.
  if (count > INT_MAX / 2) {
    throwLimit("CUDA FAS: " + std::to_string(count) + " rings in one batch; split it");
  }
  if (count > 0 && rings == nullptr) {
    throwInvalid("CUDA FAS: null ring array for " + std::to_string(count) + " rings");
  }
  if (rules.evRule == EvRule::kCrease) {
    for (int spoke : {rules.creaseSpokeA, rules.creaseSpokeB}) {
      if (spoke < 0 || spoke >= shape.spokeCount()) {
        throwInvalid("CUDA FAS: crease spoke " + std::to_string(spoke) + " outside 0.." +
                     std::to_string(shape.spokeCount() - 1));
      }
    }
  }
}

struct CudaFasBatch::Impl {
  WarpFasPlan plan;
  WarpStepProgram deviceStep;  // records in `stepWords`
  int count = 0;
  int blocks = 1;
  detail::DeviceArray<float> rings, output, scratch;
  detail::DeviceArray<uint32_t> stepWords;
  std::optional<detail::TimedStream> stream;  // created once a device is known; destroyed first
};

CudaFasBatch::CudaFasBatch(const RingRules& rules, int depth, int count, const float* hostRings)
    : impl_(std::make_unique<Impl>()) {
  validateCudaFasInput(rules, depth, count, hostRings);
  detail::requireCudaDevice();
  Impl& s = *impl_;
  s.plan = planWarpFas(rules.shape, depth);
  s.count = count;
  const int needed = (count + s.plan.warpsPerBlock - 1) / s.plan.warpsPerBlock;
  const int resident = detail::residentBlocks(s.plan);
  s.blocks = needed < resident ? (needed > 0 ? needed : 1) : resident;

  s.stream.emplace("CUDA FAS");

  const size_t ringFloats = size_t(count) * size_t(s.plan.layout.ringFloats);
  s.rings = allocate<float>(ringFloats, "cudaMalloc(rings)");
  s.output = allocate<float>(cudaFasOutputFloats(rules.shape, depth, count), "cudaMalloc(output)");
  s.scratch = allocate<float>(s.plan.scratchFloats(s.blocks), "cudaMalloc(scratch)");
  if (ringFloats > 0) {
    check(cudaMemcpy(s.rings.get(), hostRings, ringFloats * sizeof(float), cudaMemcpyHostToDevice),
          "cudaMemcpy(rings)");
  }
  const WarpStepImage step = makeWarpStepImage(rules);
  s.stepWords = detail::uploadToDevice(step.words.data(), step.words.size(), "CUDA FAS",
                                       "cudaMemcpy(step program)");
  s.deviceStep = bindWarpStep(step, s.stepWords.get());
}

CudaFasBatch::~CudaFasBatch() = default;

void CudaFasBatch::launch() {
  Impl& s = *impl_;
  detail::launchWarpFas(s.plan, s.deviceStep, s.count, s.rings.get(), s.output.get(),
                        s.scratch.get(), s.blocks, s.stream->get());
}

float CudaFasBatch::timeKernelMs(int repetitions) {
  if (repetitions < 1) throwInvalid("CUDA FAS: timing needs at least 1 repetition");
  return impl_->stream->meanMs(repetitions, [this] { launch(); });
}

std::vector<float> CudaFasBatch::download() {
  Impl& s = *impl_;
  s.stream->synchronize("FAS kernel");
  std::vector<float> result(outputFloats());
  if (!result.empty()) {
    check(cudaMemcpy(result.data(), s.output.get(), result.size() * sizeof(float),
                     cudaMemcpyDeviceToHost),
          "cudaMemcpy(output)");
  }
  return result;
}

const float* CudaFasBatch::deviceRings() const {
  return impl_->rings.get();
}
float* CudaFasBatch::deviceOutput() const {
  return impl_->output.get();
}
size_t CudaFasBatch::outputFloats() const {
  return size_t(impl_->count) * size_t(impl_->plan.layout.depth) *
         size_t(impl_->plan.layout.refinedFloats);
}
int CudaFasBatch::blocks() const {
  return impl_->blocks;
}
int CudaFasBatch::warpsPerBlock() const {
  return impl_->plan.warpsPerBlock;
}
bool CudaFasBatch::sharedBuffers() const {
  return impl_->plan.sharedBuffers;
}

std::vector<float> refineRingsCuda(const RingRules& rules, int depth, int count,
                                   const float* rings) {
  validateCudaFasInput(rules, depth, count, rings);
  if (count == 0) return {};
  CudaFasBatch batch(rules, depth, count, rings);
  batch.launch();
  return batch.download();
}

std::vector<float> refineRingsCuda(const CudaRingBatch& batch, const float* rings) {
  RingRules rules = makeRingRules(cer::RingShape{batch.valence, false}, nullptr, false);
  return refineRingsCuda(rules, batch.depth, batch.count, rings);
}

}  // namespace tessera::cuda
