#include "core/grid_evaluation.h"

#include <map>
#include <mutex>

#include <tbb/parallel_for.h>

#include "core/bicubic.h"

namespace tessera {

namespace {

// Bernstein weights of the N+1 parameters i/N, 4 per parameter.
const std::vector<float>& bernsteinTable(int level) {
  static std::mutex mutex;
  static std::map<int, std::vector<float>> tables;
  std::lock_guard<std::mutex> lock(mutex);
  auto& table = tables[level];
  if (table.empty()) {
    table.resize(size_t(level + 1) * 4);
    for (int i = 0; i <= level; ++i) {
      float w[4], unused[4];
      bernsteinBasis(float(i) / float(level), w, unused);
      for (int k = 0; k < 4; ++k) table[4 * i + k] = w[k];
    }
  }
  return table;
}

void evaluateGrid(const BezierPiece& piece, const float* weights, Vec3* out) {
  const int n = piece.level;
  const Vec3* b = piece.bezier.data();
  for (int j = 0; j <= n; ++j) {
    const float* wt = weights + 4 * j;
    // The four column curves at this t: c_k = Σ_r B_r(t) b[r][k].
    Vec3 column[4];
    for (int k = 0; k < 4; ++k) {
      column[k] = b[k] * wt[0] + b[4 + k] * wt[1] + b[8 + k] * wt[2] + b[12 + k] * wt[3];
    }
    Vec3* row = out + size_t(j) * (n + 1);
    for (int i = 0; i <= n; ++i) {
      const float* ws = weights + 4 * i;
      row[i] = column[0] * ws[0] + column[1] * ws[1] + column[2] * ws[2] + column[3] * ws[3];
    }
  }
}

}  // namespace

std::vector<size_t> gridOffsets(const std::vector<BezierPiece>& pieces) {
  std::vector<size_t> offsets(pieces.size() + 1, 0);
  for (size_t p = 0; p < pieces.size(); ++p) {
    size_t side = size_t(pieces[p].level) + 1;
    offsets[p + 1] = offsets[p] + side * side;
  }
  return offsets;
}

void evaluatePieceGrids(const std::vector<BezierPiece>& pieces, const std::vector<size_t>& offsets,
                        Vec3* out) {
  int maxLevel = 1;
  for (const BezierPiece& piece : pieces) maxLevel = std::max(maxLevel, piece.level);
  std::vector<const float*> tables(maxLevel + 1, nullptr);
  for (const BezierPiece& piece : pieces) {
    if (!tables[piece.level]) tables[piece.level] = bernsteinTable(piece.level).data();
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pieces.size(), 64), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t p = range.begin(); p != range.end(); ++p) {
      evaluateGrid(pieces[p], tables[pieces[p].level], out + offsets[p]);
    }
  });
}

}  // namespace tessera
