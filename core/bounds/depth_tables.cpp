#include "core/bounds/depth_tables.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <string>

#include "core/bounds/depth_bound.h"
#include "core/rings/fas.h"
#include "core/rings/innermost_patch.h"

namespace tessera {

namespace {

enum TableKind { kInteriorTable, kBoundaryTable };

struct TableEntry {
  TableKind kind;
  int valence;
  double c[kMaxTableDepth + 1];
};

const TableEntry kTables[] = {
#include "core/bounds/depth_tables_data.inc"
};

// Rings with sharp spokes or a corner EV, by the name of their kind's canonical rotation
// (ringKindKey): every pattern of interior rings of valence 2..8 and of open rings of 1..6 faces.
struct CreasedEntry {
  const char* key;
  double c[kMaxTableDepth + 1];
};

const CreasedEntry kCreasedTables[] = {
#include "core/bounds/depth_tables_creased.inc"
};

// Computing a bound costs about sectors · rows · N² · depth multiply-adds; beyond this budget
// (a few seconds) the a-posteriori hull bound is used instead.
constexpr double kComputeBudget = 2e9;

bool hasSharpSpokeInside(const RingRules& rules) {
  for (int s = 0; s < rules.shape.spokeCount(); ++s) {
    bool boundary = rules.shape.open && (s == 0 || s == rules.shape.sectors);
    if (!boundary && rules.spokeSharp(s)) return true;
  }
  return false;
}

const std::vector<double>* checkedInTable(const RingRules& rules) {
  if (hasSharpSpokeInside(rules) || rules.evRule == EvRule::kCorner) return nullptr;
  TableKind kind = rules.shape.open ? kBoundaryTable : kInteriorTable;
  static const auto tables = [] {
    std::map<std::pair<int, int>, std::vector<double>> byKind;
    for (const TableEntry& e : kTables) {
      byKind[{e.kind, e.valence}] = std::vector<double>(e.c, e.c + kMaxTableDepth + 1);
    }
    return byKind;
  }();
  auto found = tables.find({kind, rules.shape.sectors});
  return found == tables.end() ? nullptr : &found->second;
}

const std::vector<double>* checkedInCreasedTable(const std::string& canonicalKey) {
  static const auto tables = [] {
    std::map<std::string, std::vector<double>> byKey;
    for (const CreasedEntry& e : kCreasedTables) byKey[e.key] = std::vector<double>(e.c, e.c + kMaxTableDepth + 1);
    return byKey;
  }();
  auto found = tables.find(canonicalKey);
  return found == tables.end() ? nullptr : &found->second;
}

double computeCost(const RingRules& rules) {
  double n = rules.shape.ringPointCount();
  double rows = 48.0 * kBoundTiles + n + 16;
  return rules.shape.sectors * rows * n * n * kMaxTableDepth;
}

// A-posteriori: the limit surface lies in the hull of the ring, the approximation in the hull of
// its Bézier points, so dist ≤ max ‖q − p‖ + max ‖b − p‖ with p the EV's limit point.
double hullBound(const RingRules& rules, const float* ring) {
  auto fetch = [ring](int index) { return Vec3(ring[3 * index], ring[3 * index + 1], ring[3 * index + 2]); };
  const Vec3 evLimit = extraordinaryLimit<Vec3>(rules, fetch);
  const Vec3d limit(evLimit);
  double ringSpread = 0, approxSpread = 0;
  for (int p = 0; p < rules.shape.ringPointCount(); ++p) {
    ringSpread = std::max(ringSpread, length(Vec3d(fetch(p)) - limit));
  }
  for (int i = 0; i < rules.shape.sectors; ++i) {
    Vec3 bezier[16];
    innermostBezier<Vec3>(rules, i, fetch, bezier, &evLimit);
    for (const Vec3& b : bezier) approxSpread = std::max(approxSpread, length(Vec3d(b) - limit));
  }
  return ringSpread + approxSpread;
}

DepthEstimate estimateByRefining(const RingRules& rules, const float* ring, double tolerance) {
  std::vector<float> levels = refineRing(rules, ring, kMaxTableDepth);
  const size_t refinedFloats = size_t(rules.shape.refinedPointCount()) * 3;
  DepthEstimate estimate{0, hullBound(rules, ring)};
  for (int m = 1; m <= kMaxTableDepth && estimate.bound > tolerance; ++m) {
    estimate = {m, hullBound(rules, levels.data() + (m - 1) * refinedFloats)};
  }
  return estimate;
}

}  // namespace

double ringRadius(const RingRules& rules, const float* ring) {
  double radius = 0;
  for (int p = 0; p < rules.shape.ringPointCount(); ++p) {
    const float* q = ring + 3 * p;
    radius = std::max(radius, std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2]));
  }
  return radius;
}

// Kinds in neither table are computed once per process, for their canonical rotation: the
// coefficients a ring gets then do not depend on which rotation a process met first.
const std::vector<double>* depthCoefficients(const RingRules& rules) {
  if (const auto* table = checkedInTable(rules)) return table;
  const RingKind kind = canonicalRotation(ringKindOf(rules));
  const std::string key = ringKindKey(kind);
  if (const auto* table = checkedInCreasedTable(key)) return table;
  if (computeCost(rules) > kComputeBudget) return nullptr;
  static std::mutex mutex;
  static std::map<std::string, std::vector<double>> cache;
  {
    std::lock_guard<std::mutex> lock(mutex);
    auto found = cache.find(key);
    if (found != cache.end()) return &found->second;
  }
  std::vector<double> computed = computeDepthBound(kind);
  std::lock_guard<std::mutex> lock(mutex);
  return &cache.emplace(key, std::move(computed)).first->second;
}

DepthEstimate estimateDepth(const RingRules& rules, const float* ring, double tolerance) {
  const std::vector<double>* c = depthCoefficients(rules);
  if (c == nullptr) return estimateByRefining(rules, ring, tolerance);
  const double radius = ringRadius(rules, ring);
  int m = 0;
  while (m < kMaxTableDepth && (*c)[m] * radius > tolerance) ++m;
  return {m, (*c)[m] * radius};
}

double boundAtDepth(const RingRules& rules, const float* ring, int depth) {
  depth = std::clamp(depth, 0, kMaxTableDepth);
  if (const std::vector<double>* c = depthCoefficients(rules)) return (*c)[depth] * ringRadius(rules, ring);
  if (depth == 0) return hullBound(rules, ring);
  std::vector<float> levels = refineRing(rules, ring, depth);
  return hullBound(rules, levels.data() + size_t(depth - 1) * rules.shape.refinedPointCount() * 3);
}

}  // namespace tessera
