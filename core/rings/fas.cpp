#include "core/rings/fas.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <memory>

#include "core/base/error.h"
#include "core/rings/fas_kernel.h"

namespace tessera {

size_t ringBlockFloats(const cer::RingShape& shape) {
  return size_t(shape.ringPointCount()) * kFasBlockFloats;
}

size_t refinedBlockFloats(const cer::RingShape& shape) {
  return size_t(shape.refinedPointCount()) * kFasBlockFloats;
}

std::vector<float> packRingBlocks(const cer::RingShape& shape, const float* rings, int count) {
  const int points = shape.ringPointCount();
  const int blocks = (count + kFasLanes - 1) / kFasLanes;
  std::vector<float> packed(size_t(blocks) * ringBlockFloats(shape));
  for (int b = 0; b < blocks; ++b) {
    float* block = packed.data() + size_t(b) * ringBlockFloats(shape);
    for (int lane = 0; lane < kFasLanes; ++lane) {
      int ring = std::min(b * kFasLanes + lane, count - 1);
      const float* source = rings + size_t(ring) * points * 3;
      for (int p = 0; p < points; ++p) {
        for (int c = 0; c < 3; ++c)
          block[p * kFasBlockFloats + c * kFasLanes + lane] = source[3 * p + c];
      }
    }
  }
  return packed;
}

namespace {

// Each task's ring buffer: two refined blocks in turn, the next ring being the prefix of the
// last one. 64-byte aligned for the kernel's aligned stores; left uninitialised, since every point
// is written before it is read (zeroing it cost a memset per task).
struct RingBuffer {
  explicit RingBuffer(size_t floats)
      : storage(std::make_unique_for_overwrite<float[]>(2 * floats + 16)) {
    auto base = reinterpret_cast<uintptr_t>(storage.get());
    float* aligned = storage.get() + ((64 - base % 64) % 64) / sizeof(float);
    halves[0] = aligned;
    halves[1] = aligned + floats;
  }
  std::unique_ptr<float[]> storage;
  float* halves[2];
};

using BlockKernel = void (*)(const fas_kernel::BlockJob&, int, int);

BlockKernel blockKernel(FasKernel kernel) {
  if (!fasKernelAvailable(kernel)) throwUnsupported("this CPU has no AVX-512 for the FAS kernel");
  return kernel == FasKernel::kAvx512 ? fas_kernel::refineBlocksAvx512
                                      : fas_kernel::refineBlocksAvx2;
}

}  // namespace

bool fasKernelAvailable(FasKernel kernel) {
  return kernel == FasKernel::kAvx2 || fas_kernel::hasAvx512();
}

FasKernel fastestFasKernel() {
  static const FasKernel fastest =
      fasKernelAvailable(FasKernel::kAvx512) ? FasKernel::kAvx512 : FasKernel::kAvx2;
  return fastest;
}

void refineRingBlocks(const RingRules& rules, const float* blocks, int blockCount, int depth,
                      float* output) {
  refineRingBlocks(rules, blocks, blockCount, depth, output, fastestFasKernel());
}

void refineRingBlocks(const RingRules& rules, const float* blocks, int blockCount, int depth,
                      float* output, FasKernel kernel) {
  const BlockKernel refineBlocks = blockKernel(kernel);
  const StepProgram program = decodeStep(rules, kFasBlockFloats);
  const fas_kernel::BlockJob shared{&program,
                                    blocks,
                                    output,
                                    ringBlockFloats(rules.shape),
                                    refinedBlockFloats(rules.shape),
                                    depth,
                                    {nullptr, nullptr}};
  tbb::parallel_for(tbb::blocked_range<int>(0, blockCount, 16),
                    [&](const tbb::blocked_range<int>& range) {
                      RingBuffer buffer(shared.refinedFloats);
                      fas_kernel::BlockJob job = shared;
                      job.ringBuffer[0] = buffer.halves[0];
                      job.ringBuffer[1] = buffer.halves[1];
                      refineBlocks(job, range.begin(), range.end());
                    });
}

std::vector<float> refineRing(const RingRules& rules, const float* ring, int depth) {
  const size_t refinedFloats = size_t(rules.shape.refinedPointCount()) * 3;
  std::vector<float> result(refinedFloats * depth);
  const float* in = ring;
  for (int level = 0; level < depth; ++level) {
    float* out = result.data() + level * refinedFloats;
    refineRingStep<3>(rules, in, out);
    in = out;
  }
  return result;
}

}  // namespace tessera
