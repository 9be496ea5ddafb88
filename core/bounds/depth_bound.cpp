#include "core/bounds/depth_bound.h"

#include <algorithm>
#include <cmath>

#include "core/bounds/linear_model.h"
#include "core/rings/innermost_patch.h"
#include "core/rings/ring_patches.h"

namespace tessera {

namespace {

// Rows bounding the error on one sector, in terms of the ring at the innermost level.
struct SectorRows {
  Matrix tiles{0, 0};      // Bézier coefficients of (true − approximation) on each dyadic tile
  Matrix hullTrue{0, 0};   // ring points at depth `tiles` minus the limit point
  Matrix hullApprox{0, 0}; // approximation's control points on the tail minus the limit point
};

SectorRows sectorRows(const RingRules& rules, int sector, const RingStepMatrices& ringStep,
                      const Matrix& approximation, int tiles) {
  const int n = rules.shape.ringPointCount(), refined = rules.shape.refinedPointCount();
  const Matrix& step = ringStep.step;
  const Matrix& limit = ringStep.limit;
  SectorRows rows;
  rows.tiles = Matrix(0, n);
  Matrix power = identity(n);  // A^t
  for (int t = 0; t < tiles; ++t) {
    Matrix refinedFromRing = multiply(step, power);  // S A^t
    const double size = std::ldexp(1.0, -(t + 1));
    for (int k = 0; k < kPatchesPerSector; ++k) {
      Matrix net = linearMap(16, refined, [&](const double* points, double* out) {
        for (int r = 0; r < 4; ++r) {
          for (int c = 0; c < 4; ++c) {
            out[4 * r + c] = sectorNetPoint<double>(rules, sector, k, r, c,
                                                     [points](int index) { return points[index]; });
          }
        }
      });
      Matrix exact = multiply(bsplineToBezierMatrix(), multiply(net, refinedFromRing));
      int x0, y0;
      sectorPatchOrigin(k, x0, y0);
      Matrix restricted = multiply(restriction(x0 * size, (x0 + 1) * size, y0 * size, (y0 + 1) * size),
                                   approximation);
      for (size_t i = 0; i < exact.a.size(); ++i) exact.a[i] -= restricted.a[i];
      appendRows(rows.tiles, exact);
    }
    power = multiply(ringStep.ringStep, power);
  }
  rows.hullTrue = power;  // A^tiles
  const double tail = std::ldexp(1.0, -tiles);
  rows.hullApprox = multiply(restriction(0, tail, 0, tail), approximation);
  for (Matrix* m : {&rows.hullTrue, &rows.hullApprox}) {
    for (int r = 0; r < m->rows; ++r) {
      for (int c = 0; c < n; ++c) m->at(r, c) -= limit.at(0, c);
    }
  }
  return rows;
}

// Interior rings look the same from every sector; other kinds need every sector.
bool rotationallySymmetric(const RingKind& kind) {
  if (kind.shape.open) return false;
  for (uint8_t s : kind.sharpSpokes) {
    if (s) return false;
  }
  return true;
}

}  // namespace

std::vector<double> approximationBound(const RingRules& rules, bool oneSector, const SectorApproximation& approximate,
                                       int maxDepth, int tiles) {
  const int n = rules.shape.ringPointCount();
  const RingStepMatrices ringStep = ringStepMatrices(rules);
  Matrix tileRows(0, n), hullTrue(0, n), hullApprox(0, n);
  const int sectors = oneSector ? 1 : rules.shape.sectors;
  for (int s = 0; s < sectors; ++s) {
    const Matrix approximation =
        linearMap(16, n, [&](const double* ring, double* out) { approximate(s, ring, out); });
    SectorRows rows = sectorRows(rules, s, ringStep, approximation, tiles);
    appendRows(tileRows, rows.tiles);
    appendRows(hullTrue, rows.hullTrue);
    appendRows(hullApprox, rows.hullApprox);
  }
  std::vector<double> bound;
  for (int m = 0; m <= maxDepth; ++m) {
    double tail = maxRowNorm(hullTrue) + maxRowNorm(hullApprox);
    // ×(1 + 1e-6): headroom for the rounding of the double-precision model itself.
    bound.push_back(std::max(maxRowNorm(tileRows), tail) * (1.0 + 1e-6));
    if (m == maxDepth) break;
    tileRows = multiply(tileRows, ringStep.ringStep);
    hullTrue = multiply(hullTrue, ringStep.ringStep);
    hullApprox = multiply(hullApprox, ringStep.ringStep);
  }
  return bound;
}

RingKind ringKindOf(const RingRules& rules) {
  RingKind kind{rules.shape, {}, rules.evRule == EvRule::kCorner};
  for (int s = 0; s < rules.shape.spokeCount(); ++s) kind.sharpSpokes.push_back(rules.spokeSharp(s) ? 1 : 0);
  return kind;
}

RingKind canonicalRotation(const RingKind& kind) {
  RingKind best = kind;
  best.sharpSpokes.resize(kind.shape.spokeCount(), 0);
  if (kind.shape.open) return best;
  const std::vector<uint8_t> spokes = best.sharpSpokes;
  const int n = int(spokes.size());
  for (int r = 1; r < n; ++r) {
    std::vector<uint8_t> rotated(spokes.size());
    for (int s = 0; s < n; ++s) rotated[s] = spokes[(s + r) % n];
    if (rotated < best.sharpSpokes) best.sharpSpokes = rotated;
  }
  return best;
}

std::string ringKindKey(const RingKind& kind) {
  std::string key = std::to_string(kind.shape.sectors) + (kind.shape.open ? "o" : "c") + (kind.cornerEv ? "x" : "-");
  for (int s = 0; s < kind.shape.spokeCount(); ++s) {
    key += s < int(kind.sharpSpokes.size()) && kind.sharpSpokes[s] ? '1' : '0';
  }
  return key;
}

std::vector<double> computeDepthBound(const RingKind& kind, int maxDepth, int tiles) {
  std::vector<uint8_t> sharp = kind.sharpSpokes;
  sharp.resize(kind.shape.spokeCount(), 0);
  const RingRules rules = makeRingRules(kind.shape, sharp.data(), kind.cornerEv);
  return approximationBound(
      rules, rotationallySymmetric(kind),
      [&](int sector, const double* ring, double out[16]) {
        innermostBezier<double>(rules, sector, [ring](int index) { return ring[index]; }, out);
      },
      maxDepth, tiles);
}

}  // namespace tessera
