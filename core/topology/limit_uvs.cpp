#include "core/topology/limit_uvs.h"

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/surfaceFactoryCache.h>
#include <tbb/parallel_for.h>

#include <mutex>
#include <shared_mutex>

#include "core/topology/far_topology.h"

namespace tessera {

namespace Bfr = OpenSubdiv::Bfr;

namespace {
// Approximation levels of Bfr's irregular patches: as the tests' reference (at 6, the smoothed UVs
// of catmark_smoothtris0's triangles are still 1.8e-3 of the UV square off those at 10).
constexpr int kApproxLevel = 10;
using ThreadedCache = Bfr::SurfaceFactoryCacheThreaded<std::shared_mutex, std::shared_lock<std::shared_mutex>,
                                                       std::unique_lock<std::shared_mutex>>;
}  // namespace

// OpenSubdiv's own face-varying evaluation: Bfr over a Far refiner with the UV channel.
// Every face's surface and patch points are made once, with the patch set, so a request only
// evaluates.
struct LimitUvs::Impl {
  struct FaceSurface {
    Bfr::Surface<double> surface;
    std::vector<double> points;  // Bfr's patch points, (u, v) pairs
  };
  std::vector<FaceSurface> faces;  // a hole's surface is invalid
};

LimitUvs::LimitUvs(const ControlMesh& mesh) : impl_(std::make_unique<Impl>()) {
  const std::vector<double> values(mesh.uvs.begin(), mesh.uvs.end());
  const std::unique_ptr<Far::TopologyRefiner> refiner = createTopologyRefiner(mesh, /*withUvs=*/true);
  Bfr::SurfaceFactory::Options options;
  options.SetDefaultFVarID(0).SetApproxLevelSmooth(kApproxLevel).SetApproxLevelSharp(kApproxLevel);
  const Bfr::RefinerSurfaceFactory<ThreadedCache> factory(*refiner, options);
  impl_->faces.resize(size_t(mesh.faceCount()));
  tbb::parallel_for(0, mesh.faceCount(), [&](int f) {
    Impl::FaceSurface& face = impl_->faces[size_t(f)];
    if (!factory.InitFaceVaryingSurface(f, &face.surface)) return;
    face.points.resize(size_t(face.surface.GetNumPatchPoints()) * 2);
    face.surface.PreparePatchPoints(values.data(), 2, face.points.data(), 2);
  });
}

LimitUvs::~LimitUvs() = default;

size_t LimitUvs::bytes() const {
  size_t bytes = sizeof(Impl) + impl_->faces.capacity() * sizeof(Impl::FaceSurface);
  for (const Impl::FaceSurface& face : impl_->faces) {
    bytes += face.points.capacity() * sizeof(double);
    if (face.surface.IsValid()) bytes += size_t(face.surface.GetNumControlPoints()) * sizeof(int);
  }
  return bytes;
}

std::vector<std::array<float, 2>> LimitUvs::evaluate(const std::vector<UvQuery>& queries,
                                                     const std::function<void()>& checkpoint) const {
  std::vector<std::array<float, 2>> result(queries.size(), {0.0f, 0.0f});
  tbb::parallel_for(tbb::blocked_range<size_t>(0, queries.size(), 1024), [&](const auto& range) {
    if (checkpoint) checkpoint();
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const UvQuery& q = queries[i];
      const Impl::FaceSurface& face = impl_->faces[size_t(q.face)];
      if (!face.surface.IsValid()) continue;
      double uv[2] = {q.u, q.v};
      if (q.subFace >= 0) {
        const double sub[2] = {q.u, q.v};
        face.surface.GetParameterization().ConvertNormalizedSubFaceToCoord(q.subFace, sub, uv);
      }
      double value[2];
      face.surface.Evaluate(uv, face.points.data(), 2, value);
      result[i] = {float(value[0]), float(value[1])};
    }
  });
  return result;
}

}  // namespace tessera
