#include "bench/ring_workload.h"


#include <cstdlib>
#include <cstring>
#include <new>

#include "reference/ring_meshes.h"

namespace tessera::bench {

namespace {
}

size_t refinedBytes(const cer::RingShape& shape, int depth, int rings) {
  return size_t(rings) * size_t(depth) * size_t(shape.refinedPointCount()) * 3 * sizeof(float);
}

ControlMesh distinctRingMesh(const cer::RingShape& shape, int k) {
  return testing::makeRingMesh(shape, kFirstSeed + uint32_t(k));
}

std::vector<float> distinctRings(const cer::RingShape& shape) {
  std::vector<float> rings;
  rings.reserve(size_t(kDistinctRings) * shape.ringPointCount() * 3);
  for (int k = 0; k < kDistinctRings; ++k) {
    for (const Vec3& p : distinctRingMesh(shape, k).positions)
      rings.insert(rings.end(), {p.x, p.y, p.z});
  }
  return rings;
}

std::vector<float> tiledRings(const cer::RingShape& shape, const std::vector<float>& distinct,
                              int rings) {
  const size_t ringFloats = size_t(shape.ringPointCount()) * 3;
  std::vector<float> tiled(size_t(rings) * ringFloats);
  for (int r = 0; r < rings; ++r) {
    std::memcpy(tiled.data() + r * ringFloats, distinct.data() + (r % kDistinctRings) * ringFloats,
                ringFloats * sizeof(float));
  }
  return tiled;
}

}  // namespace tessera::bench
