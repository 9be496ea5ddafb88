#include "bench/ring_workload.h"

#include <sys/mman.h>

#include <cstdlib>
#include <cstring>
#include <new>

#include "tests/support/ring_meshes.h"

namespace tessera::bench {

namespace {
constexpr size_t kHugePage = size_t(2) << 20;
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

TouchedBuffer::TouchedBuffer(size_t floats) : floats_(floats) {
  // Huge-page alignment lets madvise back the whole range with 2 MiB pages: fewer TLB misses
  // for every method alike, so the comparison measures the methods, not page walks.
  size_t bytes = (floats * sizeof(float) + kHugePage - 1) / kHugePage * kHugePage;
  data_ = static_cast<float*>(std::aligned_alloc(kHugePage, bytes == 0 ? kHugePage : bytes));
  if (data_ == nullptr) throw std::bad_alloc();
  madvise(data_, bytes, MADV_HUGEPAGE);  // advisory: a refusal only costs speed
  std::memset(data_, 0, bytes);
}

TouchedBuffer::~TouchedBuffer() {
  std::free(data_);
}

}  // namespace tessera::bench
