#include "reference/limit_distance.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "reference/limit_projection.h"
#include "reference/triangle_bvh.h"

namespace tessera::testing {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Gauss-Newton stops once a step moves the surface point by less than this fraction of the
// diagonal: far below the 1e-4 relative tolerances measured, far above double rounding.
constexpr double kProjectionTolerance = 1e-8;

constexpr int kMaxSpatialSeeds = 16;

using Barycentric = std::array<double, 3>;

// (i, j, k)/K with i + j + k = K, corners excluded.
std::vector<Barycentric> barycentricSamples(int k) {
  std::vector<Barycentric> samples;
  for (int i = 0; i <= k; ++i) {
    for (int j = 0; i + j <= k; ++j) {
      if (i == k || j == k || i + j == 0) continue;
      samples.push_back({double(i) / k, double(j) / k, double(k - i - j) / k});
    }
  }
  return samples;
}

void validate(const TriangleMeshView& mesh, const LimitDistanceOptions& options) {
  if (options.triangleSamples < 2 || options.limitSamples < 2 || options.seedSamples < 1 ||
      options.spatialSeeds < 1 || options.spatialSeeds > kMaxSpatialSeeds || !(options.everyDomainBeyond >= 0)) {
    throw std::invalid_argument(
        "limit distance: K >= 2, S >= 2, seed samples >= 1, spatial seeds 1..16, every-domain distance >= 0");
  }
  const size_t t = mesh.triangleCount(), v = mesh.positions.size();
  if (mesh.indices.size() != 3 * t) {
    throw std::invalid_argument("limit distance: indices are not triples");
  }
  for (uint32_t i : mesh.indices) {
    if (i >= v) throw std::invalid_argument("limit distance: index out of range");
  }
  if (!mesh.vertexFace.empty() && (mesh.vertexFace.size() != v || mesh.vertexSubFace.size() != v ||
                                   mesh.vertexUv.size() != 2 * v)) {
    throw std::invalid_argument("limit distance: per-vertex parameters do not match the vertices");
  }
  if (!mesh.triangleFace.empty() &&
      (mesh.triangleFace.size() != t || mesh.triangleSubFace.size() != t ||
       mesh.cornerUv.size() != 6 * t)) {
    throw std::invalid_argument(
        "limit distance: per-triangle parameters do not match the triangles");
  }
}

struct Worst {
  double distance = -1;
  SurfaceLocation at;
  uint32_t triangle = 0;
  void offer(double d, const SurfaceLocation& where, uint32_t t) {
    if (d > distance) distance = d, at = where, triangle = t;
  }
  void offer(const Worst& o) { offer(o.distance, o.at, o.triangle); }
};

Worst combine(tbb::combinable<Worst>& perThread) {
  Worst all;
  perThread.combine_each([&](const Worst& w) { all.offer(w); });
  return all;
}

SurfaceLocation locationOf(const LimitSurface& surface, int domain, double u, double v) {
  const LimitDomain& d = surface.domains()[domain];
  return {d.face, d.subFace, u, v};
}

// The domain and corner parameters a triangle's samples are seeded from, when it has them.
struct TriangleSeed {
  int domain = -1;
  double uv[6] = {};
};

class MeshToLimit {
 public:
  MeshToLimit(const LimitSurface& surface, const TriangleMeshView& mesh,
              const LimitDistanceOptions& options)
      : surface_(surface),
        mesh_(mesh),
        options_(options),
        samples_(barycentricSamples(options.triangleSamples)),
        seeds_(surface, options.seedSamples),
        tolerance_(kProjectionTolerance * surface.diagonal()) {}

  // Phase 1 bounds every triangle from one seed per sample; phase 2 tries every seed on
  // triangles in decreasing order of their bound until no bound exceeds the maximum found.
  Worst measure(size_t& reprojected) {
    std::vector<double> bound(mesh_.triangleCount());
    auto firstPass = [&](const tbb::blocked_range<size_t>& r) {
      for (size_t t = r.begin(); t != r.end(); ++t) {
        bound[t] = triangle(uint32_t(t), false).distance;
      }
    };
    tbb::parallel_for(tbb::blocked_range<size_t>(0, bound.size(), 256), firstPass);
    return refine(bound, reprojected);
  }

  size_t sampleCount() const { return samples_.size() * mesh_.triangleCount(); }

 private:
  TriangleSeed seedOf(uint32_t t) const {
    TriangleSeed seed;
    if (!mesh_.triangleFace.empty()) {
      seed.domain = surface_.domainOf(mesh_.triangleFace[t], mesh_.triangleSubFace[t]);
      for (int k = 0; k < 6; ++k) seed.uv[k] = mesh_.cornerUv[6 * t + k];
    } else if (!mesh_.vertexFace.empty()) {
      const uint32_t* corner = &mesh_.indices[3 * t];
      for (int k = 1; k < 3; ++k) {
        if (mesh_.vertexFace[corner[k]] != mesh_.vertexFace[corner[0]] ||
            mesh_.vertexSubFace[corner[k]] != mesh_.vertexSubFace[corner[0]]) {
          return seed;
        }
      }
      seed.domain = surface_.domainOf(mesh_.vertexFace[corner[0]], mesh_.vertexSubFace[corner[0]]);
      for (int k = 0; k < 6; ++k) seed.uv[k] = mesh_.vertexUv[2 * corner[k / 2] + k % 2];
    }
    return seed;
  }

  // The nearest limit point found for one sample. With `allSeeds`: Gauss-Newton to convergence
  // from the parametric seed (if any) and from every kd-tree seed, and from every domain when
  // those leave it beyond options.everyDomainBeyond. Without (the first pass, an
  // upper bound): one Gauss-Newton step from the parametric seed, or convergence from the
  // nearest kd-tree seed when the triangle has no parameters.
  LimitPoint project(const Vec3d& p, const TriangleSeed& seed, const Barycentric& b,
                     bool allSeeds) const {
    LimitPoint best;
    if (seed.domain >= 0) {
      double u = b[0] * seed.uv[0] + b[1] * seed.uv[2] + b[2] * seed.uv[4];
      double v = b[0] * seed.uv[1] + b[1] * seed.uv[3] + b[2] * seed.uv[5];
      // A triangle straddling an n-gon's sub-faces has corners unfolded past a spoke.
      const int domain = surface_.continueDomain(seed.domain, u, v);
      if (!allSeeds) return projectOneStep(surface_, p, domain, u, v);
      best = projectInDomain(surface_, p, domain, u, v, tolerance_);
    }
    LimitPoint spatial[kMaxSpatialSeeds];
    const int count = seeds_.seeds(p, allSeeds ? options_.spatialSeeds : 1, spatial);
    for (int i = 0; i < count; ++i) {
      LimitPoint candidate =
          projectInDomain(surface_, p, spatial[i].domain, spatial[i].u, spatial[i].v, tolerance_);
      if (candidate.distance < best.distance) best = candidate;
    }
    if (allSeeds && best.distance > options_.everyDomainBeyond) {
      for (int d = 0; d < surface_.domainCount(); ++d) {
        const LimitPoint seed = seeds_.nearestIn(d, p);
        const LimitPoint candidate = projectInDomain(surface_, p, d, seed.u, seed.v, tolerance_);
        if (candidate.distance < best.distance) best = candidate;
      }
    }
    return best;
  }

  Worst triangle(uint32_t t, bool allSeeds) const {
    const TriangleSeed seed = seedOf(t);
    Vec3d corner[3];
    for (int k = 0; k < 3; ++k) corner[k] = Vec3d(mesh_.positions[mesh_.indices[3 * t + k]]);
    Worst worst;
    for (const Barycentric& b : samples_) {
      const Vec3d p = corner[0] * b[0] + corner[1] * b[1] + corner[2] * b[2];
      const LimitPoint nearest = project(p, seed, b, allSeeds);
      worst.offer(nearest.distance, locationOf(surface_, nearest.domain, nearest.u, nearest.v), t);
    }
    return worst;
  }

  // Rounds over halving bands of the bound, so that only the triangles that can matter are sorted.
  Worst refine(const std::vector<double>& bound, size_t& reprojected) const {
    double ceiling = kInfinity, largestFinite = 0;
    for (double b : bound) {
      if (b < kInfinity) largestFinite = std::max(largestFinite, b);
    }
    Worst worst;
    reprojected = 0;
    while (true) {
      double floor = ceiling == kInfinity ? largestFinite / 2 : ceiling / 2;
      // What is left below the projection's precision cannot change the result: take it all.
      if (floor < tolerance_) floor = 0;
      std::vector<uint32_t> band;
      for (size_t t = 0; t < bound.size(); ++t) {
        if (bound[t] > floor && bound[t] <= ceiling) band.push_back(uint32_t(t));
      }
      tbb::parallel_sort(band.begin(), band.end(),
                         [&](uint32_t a, uint32_t b) { return bound[a] > bound[b]; });
      reprojected += reprojectBand(band, bound, worst);
      if (worst.distance >= floor || floor <= 0) break;
      ceiling = floor;
    }
    // Every bound was zero: the distance is zero, located by the first triangle.
    if (worst.distance < 0) worst.offer(triangle(0, true)), ++reprojected;
    return worst;
  }

  // Chunks in decreasing order of bound, in parallel within a chunk; returns triangles done.
  size_t reprojectBand(const std::vector<uint32_t>& band, const std::vector<double>& bound,
                       Worst& worst) const {
    size_t done = 0, chunk = 256;
    while (done < band.size() && (worst.distance < 0 || bound[band[done]] > worst.distance)) {
      const size_t end = std::min(band.size(), done + chunk);
      tbb::combinable<Worst> perThread;
      auto reproject = [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          perThread.local().offer(triangle(band[i], true));
        }
      };
      tbb::parallel_for(tbb::blocked_range<size_t>(done, end, 16), reproject);
      worst.offer(combine(perThread));
      done = end;
      chunk = std::min<size_t>(chunk * 2, 1 << 16);
    }
    return done;
  }

  const LimitSurface& surface_;
  const TriangleMeshView& mesh_;
  const LimitDistanceOptions& options_;
  const std::vector<Barycentric> samples_;
  const LimitSeedIndex seeds_;
  const double tolerance_;
};

Worst limitToMesh(const LimitSurface& surface, const TriangleMeshView& mesh, int s) {
  const TriangleBvh bvh(mesh.positions, mesh.indices);
  tbb::combinable<Worst> perThread;
  tbb::parallel_for(
      tbb::blocked_range<int>(0, surface.domainCount(), 4), [&](const tbb::blocked_range<int>& r) {
        Worst& worst = perThread.local();
        for (int d = r.begin(); d != r.end(); ++d) {
          for (int j = 0; j < s; ++j) {
            for (int i = 0; i < s; ++i) {
              const double u = double(i) / (s - 1), v = double(j) / (s - 1);
              Vec3d x;
              surface.evaluate(d, u, v, x);
              const TriangleBvh::Nearest nearest = bvh.nearest(x);
              worst.offer(nearest.distance, locationOf(surface, d, u, v), nearest.triangle);
            }
          }
        }
      });
  return combine(perThread);
}

}  // namespace

TriangleMeshView viewOf(const TriangleMesh& mesh) {
  TriangleMeshView view;
  view.positions = mesh.positions;
  view.indices = mesh.indices;
  if (mesh.vertexFace.size() == mesh.positions.size() && !mesh.positions.empty()) {
    view.vertexFace = mesh.vertexFace;
    view.vertexSubFace = mesh.vertexSubFace;
    view.vertexUv = mesh.vertexUv;
  }
  if (!mesh.triangleFace.empty()) {
    view.triangleFace = mesh.triangleFace;
    view.triangleSubFace = mesh.triangleSubFace;
    view.cornerUv = mesh.triangleST;
  }
  return view;
}

LimitDistanceReport measureLimitDistance(const LimitSurface& surface, const TriangleMeshView& mesh,
                                         const LimitDistanceOptions& options) {
  validate(mesh, options);
  LimitDistanceReport report;
  report.diagonal = surface.diagonal();
  if (mesh.triangleCount() == 0 || surface.domainCount() == 0) {
    throw std::invalid_argument("limit distance: the mesh or the limit surface is empty");
  }
  MeshToLimit meshToLimit(surface, mesh, options);
  const Worst toLimit = meshToLimit.measure(report.trianglesReprojected);
  report.meshToLimit = toLimit.distance;
  report.meshToLimitAt = toLimit.at;
  report.meshToLimitTriangle = toLimit.triangle;
  report.meshSamples = meshToLimit.sampleCount();

  const Worst toMesh = limitToMesh(surface, mesh, options.limitSamples);
  report.limitToMesh = toMesh.distance;
  report.limitToMeshAt = toMesh.at;
  report.limitSamples = size_t(surface.domainCount()) * options.limitSamples * options.limitSamples;
  return report;
}

}  // namespace tessera::testing
