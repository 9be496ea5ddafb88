// Batches of jittered rings (reference/ring_meshes.h) and their CPU reference, in the
// layout of core/rings/fas.h refineRing: ring after ring, each its levels one after another.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/rings/fas.h"
#include "reference/ring_meshes.h"

namespace tessera::testing {

struct RingKind {
  RingKind(int sectors_, bool open_ = false, std::vector<uint8_t> sharpSpokes_ = {},
           bool cornerEv_ = false)
      : sectors(sectors_), open(open_), sharpSpokes(std::move(sharpSpokes_)), cornerEv(cornerEv_) {}

  int sectors = 0;
  bool open = false;
  std::vector<uint8_t> sharpSpokes;  // resized to spokeCount, 0 = smooth
  bool cornerEv = false;

  cer::RingShape shape() const { return {sectors, open}; }
  std::vector<uint8_t> flags() const {
    std::vector<uint8_t> f = sharpSpokes;
    f.resize(shape().spokeCount(), 0);
    return f;
  }
};

// `count` rings of one kind, ring r jittered with seed firstSeed + r.
inline std::vector<float> ringBatch(const RingKind& kind, int count, uint32_t firstSeed) {
  std::vector<float> rings;
  for (int r = 0; r < count; ++r) {
    ControlMesh mesh =
        makeRingMesh(kind.shape(), firstSeed + uint32_t(r), kind.flags(), kind.cornerEv);
    for (const Vec3& p : mesh.positions) rings.insert(rings.end(), {p.x, p.y, p.z});
  }
  return rings;
}

// core/rings/fas.h refineRing on every ring of the batch, concatenated.
inline std::vector<float> cpuReference(const RingRules& rules, int depth, int count,
                                       const std::vector<float>& rings) {
  const size_t ringFloats = size_t(rules.shape.ringPointCount()) * 3;
  std::vector<float> result;
  for (int r = 0; r < count; ++r) {
    std::vector<float> levels = refineRing(rules, rings.data() + r * ringFloats, depth);
    result.insert(result.end(), levels.begin(), levels.end());
  }
  return result;
}

// Largest |coordinate| of one ring: the scale the 1e-6 relative tolerance refers to.
inline double ringExtent(const float* ring, size_t floats) {
  double extent = 0;
  for (size_t i = 0; i < floats; ++i) extent = std::max(extent, double(std::fabs(ring[i])));
  return extent;
}

}  // namespace tessera::testing
