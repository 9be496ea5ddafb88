#include "bench/tess_depth.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <string>

#include "core/bounds/depth_bound.h"
#include "core/bounds/linear_model.h"

namespace tessera::bench {

namespace {

constexpr double kModelRounding = 1.0 + 1e-6;  // as core's tables: the model's own rounding

// The control polyhedron over sector i's innermost quad, (EV, e_i, d_i, e_next) bilinearly, as a
// degree-elevated bicubic Bézier: control point (r, c) is the quad at (s, t) = (c/3, r/3), s
// along spoke i (as in innermost_patch.h).
void bilinearQuad(const RingRules& rules, int sector, const double* ring, double out[16]) {
  const int e = cer::ringIndex(sector, cer::kE), d = cer::ringIndex(sector, cer::kD);
  const int eNext = cer::ringIndex(rules.nextSector(sector), cer::kE);
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      const double s = c / 3.0, t = r / 3.0;
      out[4 * r + c] = (1 - s) * (1 - t) * ring[0] + s * (1 - t) * ring[e] + s * t * ring[d] + (1 - s) * t * ring[eNext];
    }
  }
}

bool sameFromEverySector(const RingRules& rules) {
  if (rules.shape.open || rules.evRule != EvRule::kSmooth) return false;
  for (int s = 0; s < rules.shape.spokeCount(); ++s) {
    if (rules.spokeSharp(s)) return false;
  }
  return true;
}

// 2‖A^m − 1ℓᵀ‖∞ for m = 0..24.
std::vector<double> hullBound(const RingRules& rules) {
  const RingStepMatrices ring = ringStepMatrices(rules);
  const int n = rules.shape.ringPointCount();
  Matrix hull(n, n);
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < n; ++c) hull.at(i, c) = (i == c ? 1.0 : 0.0) - ring.limit.at(0, c);
  }
  std::vector<double> bound;
  for (int m = 0; m <= kMaxTableDepth; ++m) {
    bound.push_back(2 * maxRowNorm(hull) * kModelRounding);
    if (m == kMaxTableDepth) break;
    hull = multiply(hull, ring.ringStep);
  }
  return bound;
}

ControlMeshBounds computeBounds(const RingRules& rules) {
  ControlMeshBounds bounds;
  bounds.polyhedron = approximationBound(rules, sameFromEverySector(rules),
                                         [&](int sector, const double* ring, double out[16]) {
                                           bilinearQuad(rules, sector, ring, out);
                                         });
  bounds.hull = hullBound(rules);
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
