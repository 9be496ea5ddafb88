#include "core/uniform/uniform_grid.h"

#include <immintrin.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <map>
#include <mutex>

#include "core/request/tessellation_options.h"
#include "core/rings/ring_refinement.h"
#include "core/uniform/uniform_levels.h"

namespace tessera {

namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(float), "a control row of four points is 12 floats");

// The four basis functions of one net kind at the parameters i/N, w[k][i], zero-padded to a
// multiple of 8 so that 8-wide loads stay inside.
using BasisWeights = std::array<std::vector<float>, 4>;

// Per level: the weights of both bases (computed in double, rounded once), and for 2 <= N < 7
// each sample of the flattened grid (at least 9) as (s, t) indices: lane permutations of vectors
// over i and j.
struct LevelWeights {
  BasisWeights basis[2];  // indexed by NetBasis
  std::vector<int> sIndex, tIndex;
};

LevelWeights makeLevelWeights(int level) {
  LevelWeights table;
  const int side = level + 1;
  for (BasisWeights& weights : table.basis) {
    for (auto& w : weights) w.assign(size_t(std::max(8, (side + 7) / 8 * 8)), 0.0f);
  }
  for (int i = 0; i < side; ++i) {
    for (NetBasis basis : {NetBasis::kBSpline, NetBasis::kBezier}) {
      float w[4];
      gridWeights(basis, i, level, w);
      for (int k = 0; k < 4; ++k) table.basis[int(basis)][k][i] = w[k];
    }
  }
  if (side > 2 && side < 8) {
    for (int q = 0; q < side * side; ++q) {
      table.sIndex.push_back(q % side);
      table.tIndex.push_back(q / side);
    }
  }
  return table;
}

// Levels are looked up without a lock, once per piece.
const LevelWeights& levelWeights(int level) {
  static std::array<std::atomic<const LevelWeights*>, kMaxUniformLevel + 1> fast{};
  if (const LevelWeights* table = fast[level].load(std::memory_order_acquire)) return *table;
  static std::mutex mutex;
  static std::map<int, LevelWeights> tables;  // map nodes never move: references stay valid
  std::lock_guard<std::mutex> lock(mutex);
  auto [entry, inserted] = tables.try_emplace(level);
  if (inserted) entry->second = makeLevelWeights(level);
  fast[level].store(&entry->second, std::memory_order_release);
  return entry->second;
}

// The reference, core/math/grid_sample.h's order: four column curves per row, then the row's samples.
void evaluateScalar(const Vec3* b, int n, const BasisWeights& w, Vec3* out) {
  for (int j = 0; j <= n; ++j) {
    const float wt[4] = {w[0][j], w[1][j], w[2][j], w[3][j]};
    const Vec3 column[4] = {gridColumn(b, 0, wt), gridColumn(b, 1, wt), gridColumn(b, 2, wt),
                            gridColumn(b, 3, wt)};
    Vec3* row = out + size_t(j) * (n + 1);
    for (int i = 0; i <= n; ++i) {
      const float ws[4] = {w[0][i], w[1][i], w[2][i], w[3][i]};
      row[i] = gridSampleFromColumns(column, ws);
    }
  }
}

// ((c0 w0 + c1 w1) + c2 w2) + c3 w3: the order Vec3's operators evaluate the reference in.
inline __m256 combine(const __m256 c[4], const __m256 w[4]) {
  __m256 s = _mm256_add_ps(_mm256_mul_ps(c[0], w[0]), _mm256_mul_ps(c[1], w[1]));
  s = _mm256_add_ps(s, _mm256_mul_ps(c[2], w[2]));
  return _mm256_add_ps(s, _mm256_mul_ps(c[3], w[3]));
}

// Eight samples given as x, y, z vectors, stored as 8 xyz triples (24 floats) at dst.
inline void storeTriples(float* dst, __m256 x, __m256 y, __m256 z) {
  __m256 xy = _mm256_shuffle_ps(x, y, _MM_SHUFFLE(2, 0, 2, 0));   // x0 x2 y0 y2 | x4 x6 y4 y6
  __m256 yz = _mm256_shuffle_ps(y, z, _MM_SHUFFLE(3, 1, 3, 1));   // y1 y3 z1 z3 | ...
  __m256 zx = _mm256_shuffle_ps(z, x, _MM_SHUFFLE(3, 1, 2, 0));   // z0 z2 x1 x3 | ...
  __m256 a = _mm256_shuffle_ps(xy, zx, _MM_SHUFFLE(2, 0, 2, 0));  // x0 y0 z0 x1 | x4 y4 z4 x5
  __m256 b = _mm256_shuffle_ps(yz, xy, _MM_SHUFFLE(3, 1, 2, 0));  // y1 z1 x2 y2 | y5 z5 x6 y6
  __m256 c = _mm256_shuffle_ps(zx, yz, _MM_SHUFFLE(3, 1, 3, 1));  // z2 x3 y3 z3 | z6 x7 y7 z7
  _mm256_storeu_ps(dst, _mm256_permute2f128_ps(a, b, 0x20));
  _mm256_storeu_ps(dst + 8, _mm256_permute2f128_ps(c, a, 0x30));
  _mm256_storeu_ps(dst + 16, _mm256_permute2f128_ps(b, c, 0x31));
}

// The column curves c_k(t_j) = Σ_r B_r(t_j) b[r][k] of rows j0 … j0 + 7, as vectors over j
// (lane j − j0): [coordinate][k]. Each lane sums in the reference's order.
inline void columnCurves(const Vec3* net, const BasisWeights& w, int j0, __m256 col[3][4]) {
  const __m256 weight[4] = {_mm256_loadu_ps(w[0].data() + j0), _mm256_loadu_ps(w[1].data() + j0),
                            _mm256_loadu_ps(w[2].data() + j0), _mm256_loadu_ps(w[3].data() + j0)};
  const float* b = &net[0].x;
  for (int axis = 0; axis < 3; ++axis) {
    for (int k = 0; k < 4; ++k) {
      const float* c = b + 3 * k + axis;  // control point (r, k) at c + 12 r
      const __m256 control[4] = {_mm256_broadcast_ss(c), _mm256_broadcast_ss(c + 12),
                                 _mm256_broadcast_ss(c + 24), _mm256_broadcast_ss(c + 36)};
      col[axis][k] = combine(control, weight);
    }
  }
}

// N + 1 >= 8: the column curves of 8 rows at a time, then row by row, 8 samples at a time; the
// last vector of a row overlaps the one before it (the same values written twice) instead of a
// scalar tail.
void evaluateByRows(const Vec3* net, int level, const BasisWeights& w, Vec3* out) {
  const int side = level + 1;
  for (int j0 = 0; j0 < side; j0 += 8) {
    __m256 col[3][4];
    columnCurves(net, w, j0, col);
    alignas(32) float column[3][4][8];
    for (int axis = 0; axis < 3; ++axis) {
      for (int k = 0; k < 4; ++k) _mm256_store_ps(column[axis][k], col[axis][k]);
    }
    for (int j = j0; j < std::min(side, j0 + 8); ++j) {
      __m256 cx[4], cy[4], cz[4];
      for (int k = 0; k < 4; ++k) {
        cx[k] = _mm256_broadcast_ss(&column[0][k][j - j0]);
        cy[k] = _mm256_broadcast_ss(&column[1][k][j - j0]);
        cz[k] = _mm256_broadcast_ss(&column[2][k][j - j0]);
      }
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
}

// 2 <= N, N + 1 < 8: the column curves at every t_j fit one vector (lane j), so 8 samples anywhere
// in the grid are lane permutations of those and of the weights (N = 1 has evaluateCorners).
void evaluateFlat(const Vec3* net, int level, const LevelWeights& table, const BasisWeights& w,
                  Vec3* out) {
  const int count = (level + 1) * (level + 1);
  const __m256 weight[4] = {_mm256_loadu_ps(w[0].data()), _mm256_loadu_ps(w[1].data()),
                            _mm256_loadu_ps(w[2].data()), _mm256_loadu_ps(w[3].data())};
  __m256 col[3][4];  // [coordinate][k], lane j: column curve k at t_j
  columnCurves(net, w, 0, col);
  for (int g = 0;; g += 8) {
    g = std::max(0, std::min(g, count - 8));
    const __m256i s = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(table.sIndex.data() + g));
    const __m256i t = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(table.tIndex.data() + g));
    const __m256 ws[4] = {
        _mm256_permutevar8x32_ps(weight[0], s), _mm256_permutevar8x32_ps(weight[1], s),
        _mm256_permutevar8x32_ps(weight[2], s), _mm256_permutevar8x32_ps(weight[3], s)};
    __m256 coordinate[3];
    for (int axis = 0; axis < 3; ++axis) {
      const __m256 c[4] = {
          _mm256_permutevar8x32_ps(col[axis][0], t), _mm256_permutevar8x32_ps(col[axis][1], t),
          _mm256_permutevar8x32_ps(col[axis][2], t), _mm256_permutevar8x32_ps(col[axis][3], t)};
      coordinate[axis] = combine(c, ws);
    }
    storeTriples(&out[g].x, coordinate[0], coordinate[1], coordinate[2]);
    if (g == count - 8) return;
  }
}

// Control point q as x y z (and the next float) in both 128-bit halves; the last point is loaded
// ending at its z, so that nothing past the net is read.
inline __m256 broadcastPoint(const Vec3* net, int q) {
  if (q < 15) return _mm256_broadcast_ps(reinterpret_cast<const __m128*>(&net[q].x));
  const __m128 shifted = _mm_loadu_ps(&net[15].x - 1);  // b14.z x y z
  const __m128 point = _mm_shuffle_ps(shifted, shifted, _MM_SHUFFLE(0, 3, 2, 1));
  return _mm256_set_m128(point, point);
}

// Weights w(s0) in the low half and w(s1) in the high half.
inline __m256 halves(float low, float high) {
  return _mm256_set_m128(_mm_set1_ps(high), _mm_set1_ps(low));
}

// N = 1, the four corners (most pieces of a deeply isolated mesh such as car): points as xyz
// vectors, t = 0 in the low half and t = 1 in the high one, instead of evaluateFlat's eight lanes
// over t of which two would be used. Same operations in the same order as the reference.
void evaluateCorners(const Vec3* net, const BasisWeights& w, Vec3* out) {
  const __m256 weight[4] = {halves(w[0][0], w[0][1]), halves(w[1][0], w[1][1]),
                            halves(w[2][0], w[2][1]), halves(w[3][0], w[3][1])};
  __m256 column[4];
  for (int k = 0; k < 4; ++k) {
    const __m256 control[4] = {broadcastPoint(net, k), broadcastPoint(net, 4 + k),
                               broadcastPoint(net, 8 + k), broadcastPoint(net, 12 + k)};
    column[k] = combine(control, weight);
  }
  __m256 sample[2];  // s = 0, 1; each [t = 0 | t = 1]
  for (int i = 0; i < 2; ++i) {
    const __m256 ws[4] = {_mm256_set1_ps(w[0][i]), _mm256_set1_ps(w[1][i]),
                          _mm256_set1_ps(w[2][i]), _mm256_set1_ps(w[3][i])};
    sample[i] = combine(column, ws);
  }
  // Row-major in t: (s0,t0) (s1,t0) (s0,t1) (s1,t1); each store's fourth float is overwritten by
  // the next, and the last one stores three.
  float* dst = &out[0].x;
  _mm_storeu_ps(dst, _mm256_castps256_ps128(sample[0]));
  _mm_storeu_ps(dst + 3, _mm256_castps256_ps128(sample[1]));
  _mm_storeu_ps(dst + 6, _mm256_extractf128_ps(sample[0], 1));
  _mm_maskstore_ps(dst + 9, _mm_setr_epi32(-1, -1, -1, 0), _mm256_extractf128_ps(sample[1], 1));
}

void evaluatePiece(const Vec3* net, GridPiece piece, GridKernel kernel, Vec3* out) {
  const LevelWeights& table = levelWeights(piece.level);
  const BasisWeights& w = table.basis[int(piece.basis)];
  if (kernel == GridKernel::kScalar) {
    evaluateScalar(net, piece.level, w, out);
  } else if (piece.level == 1) {
    evaluateCorners(net, w, out);
  } else if (piece.level + 1 >= 8) {
    evaluateByRows(net, piece.level, w, out);
  } else {
    evaluateFlat(net, piece.level, table, w, out);
  }
}

// Ring r's FAS patches of levels 1..depth, then its innermost Béziers (the planner's order),
// written from pieces[0] and nets[0]. `scratch` is the thread's room for the refined rings.
void planRing(const RingSet& rings, size_t r, int p, RingWalkScratch& scratch,
              GridPiece* pieces, ControlNet* nets) {
  const int ringLevel = rings.levels[r];
  const int depth = uniformRingDepth(p, ringLevel);
  const float* innermost =
      forEachRingPatch(rings, r, depth, scratch, [&](const ControlNet& net, const PatchDomain&, int level) {
        *nets++ = net;
        *pieces++ = {uint16_t(uniformPieceLevel(p, ringLevel + level)), NetBasis::kBSpline};
      });
  const RingRules rules = rings.rules(r);
  const uint8_t* owned = rings.sectorOwned.data() + rings.sectorOffsets[r];
  const auto innermostLevel = uint16_t(uniformPieceLevel(p, ringLevel + depth));
  forEachInnermostNet(rules, innermost, rings.centers[r], owned, [&](int, const Vec3* net) {
    std::copy(net, net + 16, (nets++)->data());
    *pieces++ = {innermostLevel, NetBasis::kBezier};
  });
}

// Two passes over fixed chunks: sample counts and chunk totals, then the running sums.
void placeSamples(const std::vector<GridPiece>& pieces, std::vector<size_t>& offsets) {
  constexpr size_t kChunk = 4096;
  const size_t chunks = (pieces.size() + kChunk - 1) / kChunk;
  offsets.resize(pieces.size() + 1);
  offsets[0] = 0;
  std::vector<size_t> chunkFirst(chunks + 1, 0);
  tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
    size_t total = 0;
    for (size_t q = c * kChunk; q < std::min(pieces.size(), (c + 1) * kChunk); ++q) {
      const size_t side = size_t(pieces[q].level) + 1;
      offsets[q + 1] = side * side;
      total += side * side;
    }
    chunkFirst[c + 1] = total;
  });
  for (size_t c = 0; c < chunks; ++c) chunkFirst[c + 1] += chunkFirst[c];
  tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
    size_t running = chunkFirst[c];
    for (size_t q = c * kChunk; q < std::min(pieces.size(), (c + 1) * kChunk); ++q)
      offsets[q + 1] = running += offsets[q + 1];
  });
}

}  // namespace

void planUniformGrid(const PatchSet& patches, int p, UniformGrid& grid) {
  validateUniformLevel(p, "level");
  const RegularPatches& regular = patches.regular;
  const RingSet& rings = patches.rings;
  grid.regularPieces = regular.size();
  grid.ringFirst.resize(rings.size() + 1);
  size_t next = regular.size();
  for (size_t r = 0; r < rings.size(); ++r) {
    grid.ringFirst[r] = next;
    next += size_t(ringPieceCount(rings, r, uniformRingDepth(p, rings.levels[r])));
  }
  grid.ringFirst[rings.size()] = next;
  grid.pieces.resize(next);
  grid.ringNets.resize(next - regular.size());

  tbb::parallel_for(tbb::blocked_range<size_t>(0, regular.size(), 4096), [&](const auto& range) {
    for (size_t q = range.begin(); q != range.end(); ++q)
      grid.pieces[q] = {uint16_t(uniformPieceLevel(p, regular.levels[q])), NetBasis::kBSpline};
  });
  tbb::enumerable_thread_specific<RingWalkScratch> scratch;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rings.size(), 8), [&](const auto& range) {
    for (size_t r = range.begin(); r != range.end(); ++r) {
      const size_t first = grid.ringFirst[r];
      planRing(rings, r, p, scratch.local(), grid.pieces.data() + first,
               grid.ringNets.data() + (first - regular.size()));
    }
  });
  placeSamples(grid.pieces, grid.offsets);
}

void evaluateUniformGrid(const PatchSet& patches, const UniformGrid& grid, Vec3* out,
                         GridKernel kernel) {
  const ControlNet* regularNets = patches.regular.bspline.data();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, grid.pieces.size(), 64),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t q = range.begin(); q != range.end(); ++q) {
                        const ControlNet& net = q < grid.regularPieces
                                                    ? regularNets[q]
                                                    : grid.ringNets[q - grid.regularPieces];
                        evaluatePiece(net.data(), grid.pieces[q], kernel, out + grid.offsets[q]);
                      }
                    });
}

}  // namespace tessera
