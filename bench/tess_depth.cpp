#include "bench/tess_depth.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <string>

#include "core/bicubic.h"
#include "core/depth_bound.h"
#include "core/innermost_patch.h"
#include "core/ring_patches.h"

namespace tessera::bench {

namespace {

constexpr int kTiles = kBoundTiles;  // as core's tables: 14 dyadic tiles, then the hull tail
constexpr double kModelRounding = 1.0 + 1e-6;

// Row-major dense matrix of the offline linear model.
struct Dense {
  int rows = 0, cols = 0;
  std::vector<double> v;
  Dense() = default;
  Dense(int r, int c) : rows(r), cols(c), v(size_t(r) * c, 0.0) {}
  double* row(int r) { return v.data() + size_t(r) * cols; }
  const double* row(int r) const { return v.data() + size_t(r) * cols; }
};

Dense product(const Dense& x, const Dense& y) {
  Dense z(x.rows, y.cols);
  for (int r = 0; r < x.rows; ++r) {
    double* out = z.row(r);
    const double* in = x.row(r);
    for (int k = 0; k < x.cols; ++k) {
      if (in[k] == 0.0) continue;
      const double* yk = y.row(k);
      for (int c = 0; c < y.cols; ++c) out[c] += in[k] * yk[c];
    }
  }
  return z;
}

void append(Dense& to, const Dense& rows) {
  to.cols = rows.cols;
  to.v.insert(to.v.end(), rows.v.begin(), rows.v.end());
  to.rows += rows.rows;
}

double largestRowSum(const Dense& m) {
  double largest = 0;
  for (int r = 0; r < m.rows; ++r) {
    double sum = 0;
    for (int c = 0; c < m.cols; ++c) sum += std::fabs(m.row(r)[c]);
    largest = std::max(largest, sum);
  }
  return largest;
}

// The matrix of a linear map, one unit vector at a time.
template <class Apply>
Dense matrixOf(int outputs, int inputs, Apply apply) {
  Dense m(outputs, inputs);
  std::vector<double> unit(inputs, 0.0), image(outputs, 0.0);
  for (int c = 0; c < inputs; ++c) {
    unit[c] = 1.0;
    apply(unit.data(), image.data());
    for (int r = 0; r < outputs; ++r) m.row(r)[c] = image[r];
    unit[c] = 0.0;
  }
  return m;
}

// de Casteljau: the cubic Bézier `in` restricted to [a, b] ⊂ [0, 1].
void restrictCubic(double a, double b, const double in[4], double out[4]) {
  auto blossom = [in](double x, double y, double z) {
    // Polar form of the cubic, symmetric in x, y, z.
    double p[4] = {in[0], in[1], in[2], in[3]};
    for (double t : {x, y, z}) {
      for (int i = 0; i < 3; ++i) p[i] = p[i] + t * (p[i + 1] - p[i]);
    }
    return p[0];
  };
  out[0] = blossom(a, a, a);
  out[1] = blossom(a, a, b);
  out[2] = blossom(a, b, b);
  out[3] = blossom(b, b, b);
}

// 16×16: Bézier patch → its restriction to [s0, s1] × [t0, t1] (row-major, s along columns).
Dense tileRestriction(double s0, double s1, double t0, double t1) {
  return matrixOf(16, 16, [&](const double* in, double* out) {
    double rowsDone[16];
    for (int r = 0; r < 4; ++r) restrictCubic(s0, s1, in + 4 * r, rowsDone + 4 * r);
    for (int c = 0; c < 4; ++c) {
      double column[4] = {rowsDone[c], rowsDone[4 + c], rowsDone[8 + c], rowsDone[12 + c]}, done[4];
      restrictCubic(t0, t1, column, done);
      for (int r = 0; r < 4; ++r) out[4 * r + c] = done[r];
    }
  });
}

// The control polyhedron over sector i's innermost quad, (EV, e_i, d_i, e_next) bilinearly, as a
// degree-elevated bicubic Bézier in terms of the ring: control point (r, c) is the quad at
// (s, t) = (c/3, r/3), s along spoke i (as in innermost_patch.h).
Dense bilinearQuad(const RingRules& rules, int sector, int ringPoints) {
  Dense quad(16, ringPoints);
  const int e = cer::ringIndex(sector, cer::kE), d = cer::ringIndex(sector, cer::kD);
  const int eNext = cer::ringIndex(rules.nextSector(sector), cer::kE);
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      double s = c / 3.0, t = r / 3.0;
      double* w = quad.row(4 * r + c);
      w[0] += (1 - s) * (1 - t);
      w[e] += s * (1 - t);
      w[d] += s * t;
      w[eNext] += (1 - s) * t;
    }
  }
  return quad;
}

struct LinearRing {
  int points = 0, refined = 0;
  Dense step;      // refined set from ring (S)
  Dense ringStep;  // next ring from ring (A): the first `points` rows of S
  Dense limit;     // 1 × points: the EV's limit position (ℓᵀ)
};

LinearRing linearRing(const RingRules& rules) {
  LinearRing ring;
  ring.points = rules.shape.ringPointCount();
  ring.refined = rules.shape.refinedPointCount();
  ring.step = matrixOf(ring.refined, ring.points,
                       [&](const double* in, double* out) { refineRingStep<1, double>(rules, in, out); });
  ring.ringStep = Dense(ring.points, ring.points);
  std::copy(ring.step.v.begin(), ring.step.v.begin() + size_t(ring.points) * ring.points, ring.ringStep.v.begin());
  ring.limit = matrixOf(1, ring.points, [&](const double* in, double* out) {
    out[0] = extraordinaryLimit<double>(rules, [in](int index) { return in[index]; });
  });
  return ring;
}

// Rows whose ℓ1 norms bound the error on sector i in terms of the level-m ring: Bézier
// coefficients of (limit − quad) on every tile, then the tail's two hull terms.
void sectorRows(const RingRules& rules, int sector, const LinearRing& ring, Dense& tiles, Dense& tailTrue,
                Dense& tailQuad) {
  static const Dense toBezier =
      matrixOf(16, 16, [](const double* in, double* out) { bsplineToBezier<double>(in, out); });
  const Dense quad = bilinearQuad(rules, sector, ring.points);
  Dense power(ring.points, ring.points);  // A^t
  for (int i = 0; i < ring.points; ++i) power.row(i)[i] = 1.0;
  for (int t = 0; t < kTiles; ++t) {
    const Dense refinedFromRing = product(ring.step, power);
    const double size = std::ldexp(1.0, -(t + 1));
    for (int k = 0; k < kPatchesPerSector; ++k) {
      Dense net = matrixOf(16, ring.refined, [&](const double* points, double* out) {
        for (int r = 0; r < 4; ++r) {
          for (int c = 0; c < 4; ++c) {
            out[4 * r + c] = sectorNetPoint<double>(rules, sector, k, r, c, [points](int i) { return points[i]; });
          }
        }
      });
      Dense difference = product(toBezier, product(net, refinedFromRing));
      int x0, y0;
      sectorPatchOrigin(k, x0, y0);
      const Dense quadOnTile = product(tileRestriction(x0 * size, (x0 + 1) * size, y0 * size, (y0 + 1) * size), quad);
      for (size_t i = 0; i < difference.v.size(); ++i) difference.v[i] -= quadOnTile.v[i];
      append(tiles, difference);
    }
    power = product(ring.ringStep, power);
  }
  // Tail [0, 2^-T]²: the limit lies in the hull of the level-(m+T) ring, the quad is a convex
  // combination of its four corners there; both are compared with the limit point.
  const double tail = std::ldexp(1.0, -kTiles);
  Dense quadTail = product(tileRestriction(0, tail, 0, tail), quad);
  for (Dense* m : {&power, &quadTail}) {
    for (int r = 0; r < m->rows; ++r) {
      for (int c = 0; c < ring.points; ++c) m->row(r)[c] -= ring.limit.row(0)[c];
    }
  }
  append(tailTrue, power);
  append(tailQuad, quadTail);
}

bool sameFromEverySector(const RingRules& rules) {
  if (rules.shape.open || rules.evRule != EvRule::kSmooth) return false;
  for (int s = 0; s < rules.shape.spokeCount(); ++s) {
    if (rules.spokeSharp(s)) return false;
  }
  return true;
}

ControlMeshBounds computeBounds(const RingRules& rules) {
  const LinearRing ring = linearRing(rules);
  Dense tiles(0, ring.points), tailTrue(0, ring.points), tailQuad(0, ring.points);
  const int sectors = sameFromEverySector(rules) ? 1 : rules.shape.sectors;
  for (int i = 0; i < sectors; ++i) sectorRows(rules, i, ring, tiles, tailTrue, tailQuad);
  Dense hull(ring.points, ring.points);  // A^m − 1ℓᵀ
  for (int i = 0; i < ring.points; ++i) {
    for (int c = 0; c < ring.points; ++c) hull.row(i)[c] = (i == c ? 1.0 : 0.0) - ring.limit.row(0)[c];
  }
  ControlMeshBounds bounds;
  for (int m = 0; m <= kMaxTableDepth; ++m) {
    double tailBound = largestRowSum(tailTrue) + largestRowSum(tailQuad);
    bounds.polyhedron.push_back(std::max(largestRowSum(tiles), tailBound) * kModelRounding);
    bounds.hull.push_back(2 * largestRowSum(hull) * kModelRounding);
    if (m == kMaxTableDepth) break;
    tiles = product(tiles, ring.ringStep);
    tailTrue = product(tailTrue, ring.ringStep);
    tailQuad = product(tailQuad, ring.ringStep);
    hull = product(hull, ring.ringStep);
  }
  return bounds;
}

std::string kindKey(const RingRules& rules) {
  std::string key = std::to_string(rules.shape.sectors) + (rules.shape.open ? "o" : "c") +
                    char('0' + int(rules.evRule));
  for (int s = 0; s < rules.shape.spokeCount(); ++s) key += rules.spokeSharp(s) ? '1' : '0';
  return key;
}

}  // namespace

const ControlMeshBounds& controlMeshBounds(const RingRules& rules) {
  static std::mutex mutex;
  static std::map<std::string, ControlMeshBounds> cache;
  const std::string key = kindKey(rules);
  {
    std::lock_guard<std::mutex> lock(mutex);
    auto found = cache.find(key);
    if (found != cache.end()) return found->second;
  }
  ControlMeshBounds computed = computeBounds(rules);
  std::lock_guard<std::mutex> lock(mutex);
  return cache.emplace(key, std::move(computed)).first->second;
}

int depthFromTable(const std::vector<double>& table, double radius, double tolerance) {
  int m = 0;
  while (m + 1 < int(table.size()) && table[m] * radius > tolerance) ++m;
  return m;
}

}  // namespace tessera::bench
