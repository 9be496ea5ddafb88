// PROTOTYPE: the body of the proposed refineRingBlocks, included by fas_proposed.cpp (AVX2) and
// fas_proposed_avx512.cpp (AVX-512), each with its own TESSERA_PROPOSED_NS. Not a public header.
#pragma once

#include <immintrin.h>
#include <tbb/parallel_for.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "bench/prototype/fas_rules_proposed.h"
#include "core/fas.h"

namespace tessera::TESSERA_PROPOSED_NS {

namespace {

// PROPOSED 4: one refined point (kFasBlockFloats = 24 floats, three 32-byte vectors) per loop
// trip. The core loop moved 8 floats per trip and spent as many instructions on the loop as on
// the copy; a refined block is always a whole number of points.
void streamOut(float* destination, const float* source, size_t floats) {
  static_assert(kFasBlockFloats == 24, "one trip streams one point of a block");
  if (reinterpret_cast<uintptr_t>(destination) % 32 == 0 && floats % kFasBlockFloats == 0) {
    for (size_t i = 0; i < floats; i += kFasBlockFloats) {
      _mm256_stream_ps(destination + i, _mm256_load_ps(source + i));
      _mm256_stream_ps(destination + i + 8, _mm256_load_ps(source + i + 8));
      _mm256_stream_ps(destination + i + 16, _mm256_load_ps(source + i + 16));
    }
    return;
  }
  std::memcpy(destination, source, floats * sizeof(float));
}

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
  const StepProgram program =
      decodeStep<kFasBlockFloats>(rules);  // PROPOSED 1: once per call, not per point
  tbb::parallel_for(
      tbb::blocked_range<int>(0, blockCount, 16), [&](const tbb::blocked_range<int>& range) {
        RingBuffer buffer(refinedFloats);
        for (int b = range.begin(); b != range.end(); ++b) {
          const float* ring = blocks + size_t(b) * ringFloats;
          float* out = output + size_t(b) * depth * refinedFloats;
          for (int level = 0; level < depth; ++level) {
            float* refined = buffer.halves[level & 1];
            TESSERA_PROPOSED_NS::refineRingStep<kFasBlockFloats>(rules, program, ring, refined);
            streamOut(out + level * refinedFloats, refined, refinedFloats);
            ring = refined;
          }
        }
      });
  _mm_sfence();
}

}  // namespace tessera::TESSERA_PROPOSED_NS
