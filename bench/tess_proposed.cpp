#include "bench/tess_proposed.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "core/bicubic.h"
#include "core/fas_rules.h"
#include "core/innermost_patch.h"
#include "core/ring_patches.h"

namespace tessera::bench::proposed {

namespace {

int uniformLevel(int p, int depth) { return std::max(p >> std::min(depth, 30), 1); }

int ownedSectors(const RingSet& rings, size_t r) {
  const uint8_t* owned = rings.sectorOwned.data() + rings.sectorOffsets[r];
  int count = 0;
  for (int i = 0; i < rings.shapes[r].sectors; ++i) count += owned[i] != 0;
  return count;
}

// FAS levels of one ring, reused by a thread from ring to ring.
struct FasScratch {
  std::vector<float> levels;
};

using Weights = std::vector<float>[4];

// ((c0 w0 + c1 w1) + c2 w2) + c3 w3: the order Vec3's operators evaluate core's expressions in.
__attribute__((target("avx2"))) inline __m256 combine(const __m256 c[4], const __m256 w[4]) {
  __m256 s = _mm256_add_ps(_mm256_mul_ps(c[0], w[0]), _mm256_mul_ps(c[1], w[1]));
  s = _mm256_add_ps(s, _mm256_mul_ps(c[2], w[2]));
  return _mm256_add_ps(s, _mm256_mul_ps(c[3], w[3]));
}

// Eight samples given as x, y, z vectors, stored as 8 xyz triples (24 floats) at dst.
__attribute__((target("avx2"))) inline void storeTriples(float* dst, __m256 x, __m256 y, __m256 z) {
  __m256 xy = _mm256_shuffle_ps(x, y, _MM_SHUFFLE(2, 0, 2, 0));  // x0 x2 y0 y2 | x4 x6 y4 y6
  __m256 yz = _mm256_shuffle_ps(y, z, _MM_SHUFFLE(3, 1, 3, 1));  // y1 y3 z1 z3 | ...
  __m256 zx = _mm256_shuffle_ps(z, x, _MM_SHUFFLE(3, 1, 2, 0));  // z0 z2 x1 x3 | ...
  __m256 a = _mm256_shuffle_ps(xy, zx, _MM_SHUFFLE(2, 0, 2, 0));  // x0 y0 z0 x1 | x4 y4 z4 x5
  __m256 b = _mm256_shuffle_ps(yz, xy, _MM_SHUFFLE(3, 1, 2, 0));  // y1 z1 x2 y2 | y5 z5 x6 y6
  __m256 c = _mm256_shuffle_ps(zx, yz, _MM_SHUFFLE(3, 1, 3, 1));  // z2 x3 y3 z3 | z6 x7 y7 z7
  _mm256_storeu_ps(dst, _mm256_permute2f128_ps(a, b, 0x20));
  _mm256_storeu_ps(dst + 8, _mm256_permute2f128_ps(c, a, 0x30));
  _mm256_storeu_ps(dst + 16, _mm256_permute2f128_ps(b, c, 0x31));
}

// The first four of eight samples (N = 1): 12 floats, nothing past the piece's end.
__attribute__((target("avx2"))) inline void storeFourTriples(float* dst, __m256 x, __m256 y, __m256 z) {
  __m256 xy = _mm256_shuffle_ps(x, y, _MM_SHUFFLE(2, 0, 2, 0));
  __m256 yz = _mm256_shuffle_ps(y, z, _MM_SHUFFLE(3, 1, 3, 1));
  __m256 zx = _mm256_shuffle_ps(z, x, _MM_SHUFFLE(3, 1, 2, 0));
  __m256 a = _mm256_shuffle_ps(xy, zx, _MM_SHUFFLE(2, 0, 2, 0));
  __m256 b = _mm256_shuffle_ps(yz, xy, _MM_SHUFFLE(3, 1, 2, 0));
  __m256 c = _mm256_shuffle_ps(zx, yz, _MM_SHUFFLE(3, 1, 3, 1));
  _mm256_storeu_ps(dst, _mm256_permute2f128_ps(a, b, 0x20));
  _mm_storeu_ps(dst + 8, _mm256_castps256_ps128(c));
}

__attribute__((target("avx2"))) inline __m256 lane(__m128 v, int k) {
  return _mm256_permutevar8x32_ps(_mm256_castps128_ps256(v), _mm256_set1_epi32(k));
}

// One coordinate of the four column curves at t_j: Σ_r B_r(t_j) b[r][k], k = 0..3 in the lanes.
__attribute__((target("avx2"))) inline __m128 columns(const float* b, const __m128 wt[4]) {
  __m128 s = _mm_add_ps(_mm_mul_ps(_mm_loadu_ps(b), wt[0]), _mm_mul_ps(_mm_loadu_ps(b + 4), wt[1]));
  s = _mm_add_ps(s, _mm_mul_ps(_mm_loadu_ps(b + 8), wt[2]));
  return _mm_add_ps(s, _mm_mul_ps(_mm_loadu_ps(b + 12), wt[3]));
}

// N + 1 >= 8: row by row, 8 samples at a time; the last vector of a row overlaps the one
// before it (same values written twice) instead of a scalar tail.
__attribute__((target("avx2"))) void evaluateByRows(const float* b, int n, const Weights& w, Vec3* out) {
  const int side = n + 1;
  for (int j = 0; j < side; ++j) {
    const __m128 wt[4] = {_mm_set1_ps(w[0][j]), _mm_set1_ps(w[1][j]), _mm_set1_ps(w[2][j]), _mm_set1_ps(w[3][j])};
    const __m128 colX = columns(b, wt), colY = columns(b + 16, wt), colZ = columns(b + 32, wt);
    __m256 cx[4], cy[4], cz[4];
    for (int k = 0; k < 4; ++k) cx[k] = lane(colX, k), cy[k] = lane(colY, k), cz[k] = lane(colZ, k);
    float* row = &out[size_t(j) * side].x;
    for (int i = 0;; i += 8) {
      i = std::min(i, side - 8);
      const __m256 ws[4] = {_mm256_loadu_ps(w[0].data() + i), _mm256_loadu_ps(w[1].data() + i),
                            _mm256_loadu_ps(w[2].data() + i), _mm256_loadu_ps(w[3].data() + i)};
      storeTriples(row + 3 * i, combine(cx, ws), combine(cy, ws), combine(cz, ws));
      if (i == side - 8) break;
    }
  }
}

// N + 1 < 8: the column values of all rows fit one vector (lane j), so 8 samples anywhere in the
// grid are lane permutations of those and of the weights. With fewer than 8 samples (N = 1) the
// index tables are padded and only the piece's own samples are stored.
__attribute__((target("avx2"))) void evaluateFlat(const float* b, int n, const Weights& w, const int* sIndex,
                                                  const int* tIndex, Vec3* out) {
  const int count = (n + 1) * (n + 1);
  const __m256 weight[4] = {_mm256_loadu_ps(w[0].data()), _mm256_loadu_ps(w[1].data()),
                            _mm256_loadu_ps(w[2].data()), _mm256_loadu_ps(w[3].data())};
  __m256 col[3][4];  // [coordinate][k], lane j: column curve k at t_j
  for (int axis = 0; axis < 3; ++axis) {
    for (int k = 0; k < 4; ++k) {
      const float* c = b + 16 * axis + k;
      const __m256 control[4] = {_mm256_set1_ps(c[0]), _mm256_set1_ps(c[4]), _mm256_set1_ps(c[8]), _mm256_set1_ps(c[12])};
      col[axis][k] = combine(control, weight);  // b[r][k] · B_r(t_j), summed as core sums them
    }
  }
  for (int g = 0;; g += 8) {
    g = std::max(0, std::min(g, count - 8));
    const __m256i s = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(sIndex + g));
    const __m256i t = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(tIndex + g));
    const __m256 ws[4] = {_mm256_permutevar8x32_ps(weight[0], s), _mm256_permutevar8x32_ps(weight[1], s),
                          _mm256_permutevar8x32_ps(weight[2], s), _mm256_permutevar8x32_ps(weight[3], s)};
    __m256 coordinate[3];
    for (int axis = 0; axis < 3; ++axis) {
      const __m256 c[4] = {_mm256_permutevar8x32_ps(col[axis][0], t), _mm256_permutevar8x32_ps(col[axis][1], t),
                           _mm256_permutevar8x32_ps(col[axis][2], t), _mm256_permutevar8x32_ps(col[axis][3], t)};
      coordinate[axis] = combine(c, ws);
    }
    if (count < 8) {
      storeFourTriples(&out[0].x, coordinate[0], coordinate[1], coordinate[2]);
      break;
    }
    storeTriples(&out[g].x, coordinate[0], coordinate[1], coordinate[2]);
    if (g == count - 8) break;
  }
}

// Core's scalar expressions (kept for levels the vector paths do not take).
void evaluateScalar(const float* b, int n, const Weights& w, Vec3* out) {
  for (int j = 0; j <= n; ++j) {
    Vec3 column[4];
    for (int k = 0; k < 4; ++k) {
      auto at = [b](int q) { return Vec3(b[q], b[16 + q], b[32 + q]); };
      column[k] = at(k) * w[0][j] + at(4 + k) * w[1][j] + at(8 + k) * w[2][j] + at(12 + k) * w[3][j];
    }
    for (int i = 0; i <= n; ++i) {
      out[size_t(j) * (n + 1) + i] = column[0] * w[0][i] + column[1] * w[1][i] + column[2] * w[2][i] + column[3] * w[3][i];
    }
  }
}

void storeSoa(const Vec3 bezier[16], std::array<float, 48>& out) {
  for (int q = 0; q < 16; ++q) {
    out[q] = bezier[q].x;
    out[16 + q] = bezier[q].y;
    out[32 + q] = bezier[q].z;
  }
}

}  // namespace

void UniformPlanner::plan(const PatchSet& patches, int p) {
  const RegularPatches& regular = patches.regular;
  const RingSet& rings = patches.rings;
  const int target = int(std::ceil(std::log2(double(p))));

  // Where every ring's pieces go: owned sectors × (3 per FAS level + the innermost quad).
  ringFirst_.resize(rings.size() + 1);
  ringDepth_.resize(rings.size());
  ringFirst_[0] = regular.size();
  for (size_t r = 0; r < rings.size(); ++r) {
    ringDepth_[r] = std::max(0, target - rings.levels[r]);
    ringFirst_[r + 1] = ringFirst_[r] + size_t(ownedSectors(rings, r)) * (kPatchesPerSector * ringDepth_[r] + 1);
  }
  const size_t total = ringFirst_.back();
  bezier_.resize(total);  // same size frame after frame: no allocation, no page faults
  levels_.resize(total);

  tbb::parallel_for(tbb::blocked_range<size_t>(0, regular.size(), 1024), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      Vec3 bezier[16];
      bsplineToBezier(regular.bspline[i].data(), bezier);
      storeSoa(bezier, bezier_[i]);
      levels_[i] = uniformLevel(p, regular.levels[i]);
    }
  });

  tbb::enumerable_thread_specific<FasScratch> scratch;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rings.size(), 16), [&](const tbb::blocked_range<size_t>& range) {
    FasScratch& local = scratch.local();
    for (size_t r = range.begin(); r != range.end(); ++r) {
      const RingRules rules = rings.rules(r);
      const int depth = ringDepth_[r];
      const size_t refinedFloats = size_t(rules.shape.refinedPointCount()) * 3;
      local.levels.resize(std::max(local.levels.size(), refinedFloats * depth));
      const float* in = rings.ringPoints(r);
      for (int level = 0; level < depth; ++level) {
        refineRingStep<3>(rules, in, local.levels.data() + level * refinedFloats);
        in = local.levels.data() + level * refinedFloats;
      }
      const Vec3 center = rings.centers[r];
      const uint8_t* owned = rings.sectorOwned.data() + rings.sectorOffsets[r];
      size_t slot = ringFirst_[r];
      for (int level = 1; level <= depth; ++level) {
        const float* refined = local.levels.data() + (level - 1) * refinedFloats;
        const int pieceLevel = uniformLevel(p, rings.levels[r] + level);
        for (int i = 0; i < rules.shape.sectors; ++i) {
          if (!owned[i]) continue;
          for (int k = 0; k < kPatchesPerSector; ++k, ++slot) {
            ControlNet net;
            sectorPatchNet(rules, refined, i, k, net.data());
            for (Vec3& q : net) q += center;
            Vec3 bezier[16];
            bsplineToBezier(net.data(), bezier);
            storeSoa(bezier, bezier_[slot]);
            levels_[slot] = pieceLevel;
          }
        }
      }
      const float* innermost = depth == 0 ? rings.ringPoints(r) : local.levels.data() + (depth - 1) * refinedFloats;
      auto fetch = [innermost](int index) {
        return Vec3(innermost[3 * index], innermost[3 * index + 1], innermost[3 * index + 2]);
      };
      const int innermostLevel = uniformLevel(p, rings.levels[r] + depth);
      for (int i = 0; i < rules.shape.sectors; ++i) {
        if (!owned[i]) continue;
        Vec3 bezier[16];
        innermostBezier<Vec3>(rules, i, fetch, bezier);
        for (Vec3& q : bezier) q += center;
        storeSoa(bezier, bezier_[slot]);
        levels_[slot++] = innermostLevel;
      }
    }
  });

  offsets_.resize(total + 1);
  offsets_[0] = 0;
  for (size_t i = 0; i < total; ++i) {
    const size_t side = size_t(levels_[i]) + 1;
    offsets_[i + 1] = offsets_[i] + side * side;
  }
  if (weights_.size() < size_t(p) + 1) weights_.resize(size_t(p) + 1);
  for (int level = p;; level /= 2) {
    LevelWeights& table = weights_[level];
    if (table.w[0].empty()) {
      const int side = level + 1;
      for (auto& w : table.w) w.assign(size_t(std::max(8, (side + 7) / 8 * 8)), 0.0f);
      for (int i = 0; i < side; ++i) {
        float w[4], unused[4];
        bernsteinBasis(float(i) / float(level), w, unused);
        for (int k = 0; k < 4; ++k) table.w[k][i] = w[k];
      }
      if (side < 8) {
        for (int q = 0; q < std::max(8, side * side); ++q) {
          table.sIndex.push_back(q < side * side ? q % side : 0);
          table.tIndex.push_back(q < side * side ? q / side : 0);
        }
      }
    }
    if (level <= 1) break;
  }
}

void UniformPlanner::evaluate(Vec3* out) const {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pieces(), 64), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const int n = levels_[i];
      const LevelWeights& table = weights(n);
      const float* b = bezier_[i].data();
      if (n + 1 >= 8) {
        evaluateByRows(b, n, table.w, out + offsets_[i]);
      } else if (n >= 1) {
        evaluateFlat(b, n, table.w, table.sIndex.data(), table.tIndex.data(), out + offsets_[i]);
      } else {
        evaluateScalar(b, n, table.w, out + offsets_[i]);
      }
    }
  });
}

}  // namespace tessera::bench::proposed
