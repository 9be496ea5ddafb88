#include "bench/bfr_oracle.h"

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/surfaceFactoryCache.h>
#include <opensubdiv/bfr/tessellation.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <mutex>
#include <shared_mutex>
#include <stdexcept>
#include <string>

#include "core/base/vec3.h"
#include "core/topology/far_topology.h"

namespace tessera::bench {
namespace {

namespace OsdBfr = OpenSubdiv::Bfr;
using SharedMutex = std::shared_mutex;
using ThreadSafeCache =
    OsdBfr::SurfaceFactoryCacheThreaded<SharedMutex, std::shared_lock<SharedMutex>,
                                        std::unique_lock<SharedMutex>>;
using Factory = OsdBfr::RefinerSurfaceFactory<ThreadSafeCache>;
using Surface = OsdBfr::Surface<float>;

constexpr int kFacesPerTask = 16;

// The unit normal from Evaluate's derivatives, written as xyz at `out` (left as the cross
// product where it vanishes).
void writeNormal(const float du[3], const float dv[3], float* out) {
  Vec3 n = cross(Vec3(du[0], du[1], du[2]), Vec3(dv[0], dv[1], dv[2]));
  const float l = length(n);
  if (l > 0) n = n * (1 / l);
  out[0] = n.x, out[1] = n.y, out[2] = n.z;
}

// Per thread: what one face's evaluation needs, reused from face to face.
struct Scratch {
  Surface surface;
  std::vector<float> patchPoints, uv;
};

// Positions and normals at one face's tessellation coordinates, its patch points from `points`.
void evaluateFace(const Surface& surface, const OsdBfr::Tessellation& tessellation,
                  const float* points, Scratch& local, float* position, float* normal) {
  local.patchPoints.resize(size_t(surface.GetNumPatchPoints()) * 3);
  surface.PreparePatchPoints(points, 3, local.patchPoints.data(), 3);
  local.uv.resize(2 * size_t(tessellation.GetNumCoords()));
  tessellation.GetCoords(local.uv.data());
  for (int i = 0; i < tessellation.GetNumCoords(); ++i) {
    float du[3], dv[3];
    surface.Evaluate(local.uv.data() + 2 * i, local.patchPoints.data(), 3, position + 3 * i, du,
                     dv);
    writeNormal(du, dv, normal + 3 * i);
  }
}

}  // namespace

struct BfrOracle::Osd {
  std::unique_ptr<Far::TopologyRefiner> refiner;
  std::unique_ptr<Factory> factory;
  std::vector<Surface> surfaces;  // prepareSurfaces: one per face, invalid for holes
};

BfrOracle::BfrOracle(const ControlMesh& mesh, int rate)
    : faceCount_(mesh.faceCount()), rate_(rate), osd_(std::make_unique<Osd>()) {
  osd_->refiner = createTopologyRefiner(mesh);
  osd_->factory = std::make_unique<Factory>(*osd_->refiner);  // Bfr's default approximation levels
  std::vector<uint8_t> hole(faceCount_, 0);
  for (int f : mesh.holes) hole[f] = 1;
  vertexFirst_.assign(1, 0);
  facetFirst_.assign(1, 0);
  for (int f = 0; f < faceCount_; ++f) {
    const OsdBfr::Tessellation t(
        OsdBfr::Parameterization(OpenSubdiv::Sdc::SCHEME_CATMARK, mesh.faceSizes[f]), rate);
    vertexFirst_.push_back(vertexFirst_.back() + (hole[f] ? 0 : size_t(t.GetNumCoords())));
    facetFirst_.push_back(facetFirst_.back() + (hole[f] ? 0 : size_t(t.GetNumFacets())));
  }
  positions_.assign(3 * vertexFirst_.back(), 1.0f);
  normals_.assign(3 * vertexFirst_.back(), 1.0f);
  indices_.assign(3 * facetFirst_.back(), 1);
}

BfrOracle::~BfrOracle() = default;

void BfrOracle::run(const float* points) {
  tbb::enumerable_thread_specific<Scratch> scratch;
  tbb::parallel_for(tbb::blocked_range<int>(0, faceCount_, kFacesPerTask), [&](const auto& range) {
    Scratch& local = scratch.local();
    for (int f = range.begin(); f != range.end(); ++f) {
      if (vertexFirst_[f + 1] == vertexFirst_[f] ||
          !osd_->factory->InitVertexSurface(f, &local.surface))
        continue;
      OsdBfr::Tessellation tessellation(local.surface.GetParameterization(), rate_);
      evaluateFace(local.surface, tessellation, points, local,
                   positions_.data() + 3 * vertexFirst_[f], normals_.data() + 3 * vertexFirst_[f]);
      int* facets = indices_.data() + 3 * facetFirst_[f];
      tessellation.GetFacets(facets);
      tessellation.TransformFacetCoordIndices(facets, int(vertexFirst_[f]));
    }
  });
}

void BfrOracle::prepareSurfaces() {
  std::vector<Surface>& surfaces = osd_->surfaces;
  if (!surfaces.empty()) return;
  surfaces.resize(faceCount_);
  tbb::parallel_for(tbb::blocked_range<int>(0, faceCount_, kFacesPerTask), [&](const auto& range) {
    for (int f = range.begin(); f != range.end(); ++f) {
      if (vertexFirst_[f + 1] == vertexFirst_[f]) continue;
      if (!osd_->factory->InitVertexSurface(f, &surfaces[f])) {
        throw std::runtime_error("Bfr has no surface for face " + std::to_string(f));
      }
      OsdBfr::Tessellation tessellation(surfaces[f].GetParameterization(), rate_);
      int* facets = indices_.data() + 3 * facetFirst_[f];
      tessellation.GetFacets(facets);
      tessellation.TransformFacetCoordIndices(facets, int(vertexFirst_[f]));
    }
  });
}

void BfrOracle::runPrepared(const float* points) {
  const std::vector<Surface>& surfaces = osd_->surfaces;
  tbb::enumerable_thread_specific<Scratch> scratch;
  tbb::parallel_for(tbb::blocked_range<int>(0, faceCount_, kFacesPerTask), [&](const auto& range) {
    Scratch& local = scratch.local();
    for (int f = range.begin(); f != range.end(); ++f) {
      if (!surfaces[f].IsValid()) continue;
      OsdBfr::Tessellation tessellation(surfaces[f].GetParameterization(), rate_);
      evaluateFace(surfaces[f], tessellation, points, local,
                   positions_.data() + 3 * vertexFirst_[f], normals_.data() + 3 * vertexFirst_[f]);
    }
  });
}

}  // namespace tessera::bench
