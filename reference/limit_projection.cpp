#include "reference/limit_projection.h"

#include <algorithm>
#include <cmath>

#include <nanoflann.hpp>
#include <tbb/parallel_for.h>

namespace tessera::testing {

namespace {

struct Evaluation {
  Vec3d f, fu, fv;
  double e2 = 0;  // |f - p|^2
};

Evaluation evaluateAt(const LimitSurface& surface, int domain, double u, double v, const Vec3d& p) {
  Evaluation e;
  surface.evaluate(domain, u, v, e.f, &e.fu, &e.fv);
  const Vec3d r = e.f - p;
  e.e2 = dot(r, r);
  return e;
}

// Gauss-Newton step for min |f - p|^2 with coordinates on the border of [0,1]^2 held when the
// descent direction leaves the domain (a projected Newton method on the active set).
void gaussNewtonStep(const Evaluation& e, const Vec3d& p, double u, double v, double step[2]) {
  const Vec3d r = e.f - p;
  const double g[2] = {dot(e.fu, r), dot(e.fv, r)};
  double h[3] = {dot(e.fu, e.fu), dot(e.fu, e.fv), dot(e.fv, e.fv)};
  const bool heldU = (u <= 0 && g[0] > 0) || (u >= 1 && g[0] < 0);
  const bool heldV = (v <= 0 && g[1] > 0) || (v >= 1 && g[1] < 0);
  // A small ridge keeps the system solvable where a derivative vanishes (a parametric corner
  // of an n-gon sub-face, a collapsed Bfr derivative at an extraordinary vertex).
  const double ridge = 1e-12 * (h[0] + h[2]) + 1e-300;
  h[0] += ridge, h[2] += ridge;
  step[0] = step[1] = 0;
  if (heldU && heldV) return;
  if (heldU) {
    step[1] = -g[1] / h[2];
  } else if (heldV) {
    step[0] = -g[0] / h[0];
  } else {
    const double det = h[0] * h[2] - h[1] * h[1];
    step[0] = -(h[2] * g[0] - h[1] * g[1]) / det;
    step[1] = -(h[0] * g[1] - h[1] * g[0]) / det;
  }
}

// Gauss-Newton with step halving inside one domain; `across` tells whether the minimum is held on
// the u = 1 or v = 1 border (an n-gon sub-face's spokes) by a gradient pointing past it.
LimitPoint descend(const LimitSurface& surface, const Vec3d& p, int domain, double u, double v,
                   double tolerance, int maxIterations, bool& across) {
  u = std::clamp(u, 0.0, 1.0), v = std::clamp(v, 0.0, 1.0);
  Evaluation e = evaluateAt(surface, domain, u, v, p);
  for (int iteration = 0; iteration < maxIterations; ++iteration) {
    double step[2];
    gaussNewtonStep(e, p, u, v, step);
    bool improved = false;
    double moved = 0;
    // Halve the step until the distance decreases: Gauss-Newton overshoots where the surface
    // curves strongly relative to the distance.
    for (int halving = 0; halving < 30 && !improved; ++halving, step[0] *= 0.5, step[1] *= 0.5) {
      const double nu = std::clamp(u + step[0], 0.0, 1.0), nv = std::clamp(v + step[1], 0.0, 1.0);
      if (nu == u && nv == v) break;
      Evaluation next = evaluateAt(surface, domain, nu, nv, p);
      if (next.e2 < e.e2) {
        moved = length(next.f - e.f);
        u = nu, v = nv, e = next, improved = true;
      }
    }
    if (!improved || moved < tolerance) break;
  }
  const Vec3d r = e.f - p;
  across = (u >= 1 && dot(e.fu, r) < 0) || (v >= 1 && dot(e.fv, r) < 0);
  return {domain, u, v, e.f, std::sqrt(e.e2)};
}

}  // namespace

LimitPoint projectInDomain(const LimitSurface& surface, const Vec3d& p, int domain, double u,
                           double v, double tolerance, int maxIterations) {
  bool across = false;
  LimitPoint best = descend(surface, p, domain, u, v, tolerance, maxIterations, across);
  // An n-gon has as many sub-faces as sides: that many hops reach any of them.
  const LimitDomain& start = surface.domains()[domain];
  const int hops =
      start.subFace < 0 ? 0 : int(surface.baseLevel().GetFaceVertices(start.face).size());
  for (int hop = 0; hop < hops && across; ++hop) {
    // Just past the spoke: continueDomain maps u or v = 1 + δ into the neighbour.
    double nu = best.u >= 1 ? 1 + 1e-9 : best.u, nv = best.v >= 1 && best.u < 1 ? 1 + 1e-9 : best.v;
    const int next = surface.continueDomain(best.domain, nu, nv);
    if (next == best.domain) break;
    const LimitPoint further = descend(surface, p, next, nu, nv, tolerance, maxIterations, across);
    if (further.distance >= best.distance) break;
    best = further;
  }
  return best;
}

LimitPoint projectOneStep(const LimitSurface& surface, const Vec3d& p, int domain, double u,
                          double v) {
  u = std::clamp(u, 0.0, 1.0), v = std::clamp(v, 0.0, 1.0);
  const Evaluation e = evaluateAt(surface, domain, u, v, p);
  double step[2];
  gaussNewtonStep(e, p, u, v, step);
  const double nu = std::clamp(u + step[0], 0.0, 1.0), nv = std::clamp(v + step[1], 0.0, 1.0);
  Vec3d x;
  surface.evaluate(domain, nu, nv, x);
  const double d = length(x - p), d0 = std::sqrt(e.e2);
  if (d < d0) return {domain, nu, nv, x, d};
  return {domain, u, v, e.f, d0};
}

struct LimitSeedIndex::Cloud {
  std::vector<float> xyz;
  size_t kdtree_get_point_count() const { return xyz.size() / 3; }
  float kdtree_get_pt(size_t i, size_t k) const { return xyz[3 * i + k]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

struct LimitSeedIndex::Tree
    : nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud>, Cloud, 3,
                                          uint32_t> {
  using KDTreeSingleIndexAdaptor::KDTreeSingleIndexAdaptor;
};

LimitSeedIndex::LimitSeedIndex(const LimitSurface& surface, int samplesPerSide)
    : samplesPerSide_(samplesPerSide), cloud_(std::make_unique<Cloud>()) {
  const size_t perDomain = size_t(samplesPerSide) * samplesPerSide;
  cloud_->xyz.resize(3 * perDomain * surface.domainCount());
  tbb::parallel_for(0, surface.domainCount(), [&](int d) {
    for (size_t i = 0; i < perDomain; ++i) {
      LimitPoint s = sampleAt(uint32_t(d * perDomain + i));
      Vec3d x;
      surface.evaluate(d, s.u, s.v, x);
      float* out = &cloud_->xyz[3 * (d * perDomain + i)];
      out[0] = float(x.x), out[1] = float(x.y), out[2] = float(x.z);
    }
  });
  tree_ = std::make_unique<Tree>(3, *cloud_, nanoflann::KDTreeSingleIndexAdaptorParams(16));
}

LimitSeedIndex::~LimitSeedIndex() = default;

LimitPoint LimitSeedIndex::sampleAt(uint32_t index) const {
  const uint32_t perDomain = uint32_t(samplesPerSide_) * samplesPerSide_;
  const uint32_t local = index % perDomain;
  LimitPoint s;
  s.domain = int(index / perDomain);
  s.u = (double(local % samplesPerSide_) + 0.5) / samplesPerSide_;
  s.v = (double(local / samplesPerSide_) + 0.5) / samplesPerSide_;
  return s;
}

int LimitSeedIndex::seeds(const Vec3d& p, int count, LimitPoint* out) const {
  constexpr int kCandidates = 32;
  const float query[3] = {float(p.x), float(p.y), float(p.z)};
  uint32_t index[kCandidates];
  float d2[kCandidates];
  const int found = int(tree_->knnSearch(query, kCandidates, index, d2));
  int written = 0;
  for (int i = 0; i < found && written < count; ++i) {
    LimitPoint s = sampleAt(index[i]);
    const bool seen =
        std::any_of(out, out + written, [&](const LimitPoint& o) { return o.domain == s.domain; });
    if (!seen) out[written++] = s;
  }
  return written;
}

LimitPoint LimitSeedIndex::nearestIn(int domain, const Vec3d& p) const {
  const uint32_t perDomain = uint32_t(samplesPerSide_) * samplesPerSide_;
  uint32_t best = uint32_t(domain) * perDomain;
  double bestSquared = std::numeric_limits<double>::infinity();
  for (uint32_t i = best; i < (uint32_t(domain) + 1) * perDomain; ++i) {
    const float* x = &cloud_->xyz[3 * size_t(i)];
    const double squared = (x[0] - p.x) * (x[0] - p.x) + (x[1] - p.y) * (x[1] - p.y) + (x[2] - p.z) * (x[2] - p.z);
    if (squared < bestSquared) bestSquared = squared, best = i;
  }
  return sampleAt(best);
}

}  // namespace tessera::testing
