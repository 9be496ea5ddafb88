#include "core/grid_evaluation.h"

#include <immintrin.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <map>
#include <mutex>

#include "core/bicubic.h"

namespace tessera {

namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(float), "a control row of four points is 12 floats");

// Bernstein weights of the parameters i/N, w[k][i] (bernsteinBasis in float), zero-padded to a
// multiple of 8 so that 8-wide loads stay inside. Levels with N + 1 < 8 also list each sample of
// the flattened grid as (s, t) indices, padded to 8: lane permutations of vectors over i and j.
struct LevelWeights {
  std::vector<float> w[4];
  std::vector<int> sIndex, tIndex;
};

LevelWeights makeLevelWeights(int level) {
  LevelWeights table;
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
  return table;
}

// Levels up to the largest uniform level are looked up without a lock, once per piece.
constexpr int kLockFreeLevels = 4097;

const LevelWeights& levelWeights(int level) {
  static std::array<std::atomic<const LevelWeights*>, kLockFreeLevels> fast{};
  if (level < kLockFreeLevels) {
    if (const LevelWeights* table = fast[level].load(std::memory_order_acquire)) return *table;
  }
  static std::mutex mutex;
  static std::map<int, LevelWeights> tables;  // map nodes never move: references stay valid
  std::lock_guard<std::mutex> lock(mutex);
  auto [entry, inserted] = tables.try_emplace(level);
  if (inserted) entry->second = makeLevelWeights(level);
  if (level < kLockFreeLevels) fast[level].store(&entry->second, std::memory_order_release);
  return entry->second;
}

// The reference: four column curves c_k = Σ_r B_r(t) b[r][k] per row, then Σ_k B_k(s) c_k.
void evaluateScalar(const BezierPiece& piece, const LevelWeights& table, Vec3* out) {
  const int n = piece.level;
  const Vec3* b = piece.bezier.data();
  const auto& w = table.w;
  for (int j = 0; j <= n; ++j) {
    Vec3 column[4];
    for (int k = 0; k < 4; ++k) {
      column[k] = b[k] * w[0][j] + b[4 + k] * w[1][j] + b[8 + k] * w[2][j] + b[12 + k] * w[3][j];
    }
    Vec3* row = out + size_t(j) * (n + 1);
    for (int i = 0; i <= n; ++i) {
      row[i] =
          column[0] * w[0][i] + column[1] * w[1][i] + column[2] * w[2][i] + column[3] * w[3][i];
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

// The first four of eight samples (N = 1): 12 floats, nothing past the piece's end.
inline void storeFourTriples(float* dst, __m256 x, __m256 y, __m256 z) {
  __m256 xy = _mm256_shuffle_ps(x, y, _MM_SHUFFLE(2, 0, 2, 0));
  __m256 yz = _mm256_shuffle_ps(y, z, _MM_SHUFFLE(3, 1, 3, 1));
  __m256 zx = _mm256_shuffle_ps(z, x, _MM_SHUFFLE(3, 1, 2, 0));
  __m256 a = _mm256_shuffle_ps(xy, zx, _MM_SHUFFLE(2, 0, 2, 0));
  __m256 b = _mm256_shuffle_ps(yz, xy, _MM_SHUFFLE(3, 1, 2, 0));
  __m256 c = _mm256_shuffle_ps(zx, yz, _MM_SHUFFLE(3, 1, 3, 1));
  _mm256_storeu_ps(dst, _mm256_permute2f128_ps(a, b, 0x20));
  _mm_storeu_ps(dst + 8, _mm256_castps256_ps128(c));
}

// The column curves c_k(t_j) = Σ_r B_r(t_j) b[r][k] of rows j0 … j0 + 7, as vectors over j
// (lane j − j0): [coordinate][k]. Each lane sums in the reference's order.
inline void columnCurves(const BezierPiece& piece, const LevelWeights& table, int j0,
                         __m256 col[3][4]) {
  const auto& w = table.w;
  const __m256 weight[4] = {_mm256_loadu_ps(w[0].data() + j0), _mm256_loadu_ps(w[1].data() + j0),
                            _mm256_loadu_ps(w[2].data() + j0), _mm256_loadu_ps(w[3].data() + j0)};
  const float* b = &piece.bezier[0].x;
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
void evaluateByRows(const BezierPiece& piece, const LevelWeights& table, Vec3* out) {
  const int side = piece.level + 1;
  const auto& w = table.w;
  for (int j0 = 0; j0 < side; j0 += 8) {
    __m256 col[3][4];
    columnCurves(piece, table, j0, col);
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

// N + 1 < 8: the column curves at every t_j fit one vector (lane j), so 8 samples anywhere in the
// grid are lane permutations of those and of the weights. With fewer than 8 samples (N = 1) the
// index tables are padded and only the piece's own samples are stored.
void evaluateFlat(const BezierPiece& piece, const LevelWeights& table, Vec3* out) {
  const int count = (piece.level + 1) * (piece.level + 1);
  const auto& w = table.w;
  const __m256 weight[4] = {_mm256_loadu_ps(w[0].data()), _mm256_loadu_ps(w[1].data()),
                            _mm256_loadu_ps(w[2].data()), _mm256_loadu_ps(w[3].data())};
  __m256 col[3][4];  // [coordinate][k], lane j: column curve k at t_j
  columnCurves(piece, table, 0, col);
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
    if (count < 8) {
      storeFourTriples(&out[0].x, coordinate[0], coordinate[1], coordinate[2]);
      return;
    }
    storeTriples(&out[g].x, coordinate[0], coordinate[1], coordinate[2]);
    if (g == count - 8) return;
  }
}

void evaluatePiece(const BezierPiece& piece, GridKernel kernel, Vec3* out) {
  const LevelWeights& table = levelWeights(piece.level);
  if (kernel == GridKernel::kScalar) {
    evaluateScalar(piece, table, out);
  } else if (piece.level + 1 >= 8) {
    evaluateByRows(piece, table, out);
  } else {
    evaluateFlat(piece, table, out);
  }
}

}  // namespace

// Two passes over fixed chunks: sample counts and chunk totals, then the running sums. The
// pieces (far larger than the caches) are read once, by all cores; the second pass reads only
// the offsets just written.
void gridOffsets(const std::vector<BezierPiece>& pieces, std::vector<size_t>& offsets) {
  constexpr size_t kChunk = 4096;
  const size_t chunks = (pieces.size() + kChunk - 1) / kChunk;
  offsets.resize(pieces.size() + 1);
  offsets[0] = 0;
  std::vector<size_t> chunkFirst(chunks + 1, 0);
  tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
    size_t total = 0;
    for (size_t p = c * kChunk; p < std::min(pieces.size(), (c + 1) * kChunk); ++p) {
      const size_t side = size_t(pieces[p].level) + 1;
      offsets[p + 1] = side * side;
      total += side * side;
    }
    chunkFirst[c + 1] = total;
  });
  for (size_t c = 0; c < chunks; ++c) chunkFirst[c + 1] += chunkFirst[c];
  tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
    size_t running = chunkFirst[c];
    for (size_t p = c * kChunk; p < std::min(pieces.size(), (c + 1) * kChunk); ++p)
      offsets[p + 1] = running += offsets[p + 1];
  });
}

void evaluatePieceGrids(const std::vector<BezierPiece>& pieces, const std::vector<size_t>& offsets,
                        Vec3* out, GridKernel kernel) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pieces.size(), 64),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t p = range.begin(); p != range.end(); ++p)
                        evaluatePiece(pieces[p], kernel, out + offsets[p]);
                    });
}

}  // namespace tessera
