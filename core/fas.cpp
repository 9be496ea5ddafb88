#include "core/fas.h"

#include <cstring>

#include <tbb/parallel_for.h>

#if defined(__AVX__)
#include <immintrin.h>
#endif

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
        for (int c = 0; c < 3; ++c) block[p * kFasBlockFloats + c * kFasLanes + lane] = source[3 * p + c];
      }
    }
  }
  return packed;
}

namespace {

// The refined sets are written once and not read back here: stream them past the cache.
void streamOut(float* destination, const float* source, size_t floats) {
#if defined(__AVX__)
  if (reinterpret_cast<uintptr_t>(destination) % 32 == 0) {
    for (size_t i = 0; i < floats; i += 8) {
      _mm256_stream_ps(destination + i, _mm256_load_ps(source + i));
    }
    return;
  }
#endif
  std::memcpy(destination, source, floats * sizeof(float));
}

// The ring buffer: two refined sets in turn; the next ring is the prefix of the last one.
struct alignas(64) RingBuffer {
  explicit RingBuffer(size_t floats) : storage(2 * floats + 16) {
    auto base = reinterpret_cast<uintptr_t>(storage.data());
    float* aligned = storage.data() + ((32 - base % 32) % 32) / sizeof(float);
    halves[0] = aligned;
    halves[1] = aligned + floats;
  }
  std::vector<float> storage;
  float* halves[2];
};

}  // namespace

void refineRingBlocks(const RingRules& rules, const float* blocks, int blockCount, int depth,
                      float* output) {
  const size_t ringFloats = ringBlockFloats(rules.shape);
  const size_t refinedFloats = refinedBlockFloats(rules.shape);
  tbb::parallel_for(tbb::blocked_range<int>(0, blockCount, 16), [&](const tbb::blocked_range<int>& range) {
    RingBuffer buffer(refinedFloats);
    for (int b = range.begin(); b != range.end(); ++b) {
      const float* ring = blocks + size_t(b) * ringFloats;
      float* out = output + size_t(b) * depth * refinedFloats;
      for (int level = 0; level < depth; ++level) {
        float* refined = buffer.halves[level & 1];
        refineRingStep<kFasBlockFloats>(rules, ring, refined);
        streamOut(out + level * refinedFloats, refined, refinedFloats);
        ring = refined;
      }
    }
  });
#if defined(__AVX__)
  _mm_sfence();
#endif
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
