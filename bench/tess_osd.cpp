#include "bench/tess_osd.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <shared_mutex>
#include <stdexcept>
#include <string>

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/surfaceFactoryCache.h>
#include <opensubdiv/bfr/tessellation.h>
#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/ptexIndices.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/osd/bufferDescriptor.h>
#include <opensubdiv/osd/cpuPatchTable.h>
#include <opensubdiv/osd/ompEvaluator.h>
#include <opensubdiv/osd/types.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "core/topology/far_topology.h"

namespace tessera::bench {

namespace OsdBfr = OpenSubdiv::Bfr;
namespace Osd = OpenSubdiv::Osd;

namespace {

using SharedMutex = std::shared_mutex;
using ThreadSafeCache = OsdBfr::SurfaceFactoryCacheThreaded<SharedMutex, std::shared_lock<SharedMutex>,
                                                            std::unique_lock<SharedMutex>>;
using Factory = OsdBfr::RefinerSurfaceFactory<ThreadSafeCache>;
using Surface = OsdBfr::Surface<float>;

OsdBfr::Parameterization faceParameterization(int faceSize) {
  return OsdBfr::Parameterization(OpenSubdiv::Sdc::SCHEME_CATMARK, faceSize);
}

// Patch points for Far's stencil tables: Clear/AddWithWeight is the interface UpdateValues wants.
struct StencilPoint {
  float p[3];
  void Clear() { p[0] = p[1] = p[2] = 0.0f; }
  void AddWithWeight(const StencilPoint& src, float weight) {
    for (int k = 0; k < 3; ++k) p[k] += weight * src.p[k];
  }
};

// The same adaptive refinement as core/topology/patch_builder.cpp (isolation max(2, ⌈s⌉ + 1) ≤ 10,
// secondary level 2, infinitely sharp patches, no single-crease patches), with the end caps
// OpenSubdiv recommends for evaluation (Gregory basis).
Far::PatchTableFactory::Options patchOptions(const ControlMesh& mesh) {
  int isolation = std::min(std::max(2, int(std::ceil(maxSemiSharpness(mesh))) + 1), 10);
  Far::PatchTableFactory::Options options(isolation);
  options.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
  options.useInfSharpPatch = true;
  options.useSingleCreasePatch = false;
  options.generateLegacySharpCornerPatches = false;
  return options;
}

}  // namespace

struct OsdUniformSamples::Bfr {
  std::unique_ptr<Far::TopologyRefiner> refiner;
  std::unique_ptr<Factory> factory;
  // Prepared variant.
  std::vector<Surface> surfaces;
  std::vector<size_t> patchPointOffsets;  // floats
  std::vector<float> patchPoints;
  std::vector<float> uv;  // 2 per sample, same order as the output
};

struct OsdUniformSamples::Eval {
  std::unique_ptr<Far::TopologyRefiner> refiner;
  std::unique_ptr<Far::PatchTable> table;
  Osd::CpuPatchTable* cpuTable = nullptr;
  std::vector<StencilPoint> points;  // control, refined and end-cap points
  std::vector<Osd::PatchCoord> coords;
  ~Eval() { delete cpuTable; }
};

OsdUniformSamples::OsdUniformSamples(const ControlMesh& mesh, int rate) : mesh_(mesh), rate_(rate) {
  for (const Vec3& p : mesh.positions) meshPoints_.insert(meshPoints_.end(), {p.x, p.y, p.z});
  std::vector<bool> hole(mesh.faceCount(), false);
  for (int h : mesh.holes) hole[h] = true;
  faceOffsets_.assign(1, 0);
  for (int f = 0; f < mesh.faceCount(); ++f) {
    size_t count = 0;
    if (!hole[f]) count = size_t(OsdBfr::Tessellation(faceParameterization(mesh.faceSizes[f]), rate).GetNumCoords());
    faceOffsets_.push_back(faceOffsets_.back() + count);
  }
  bfr_ = std::make_unique<Bfr>();
  bfr_->refiner = createTopologyRefiner(mesh);
  bfr_->factory = std::make_unique<Factory>(*bfr_->refiner);  // Bfr's default approximation levels
}

OsdUniformSamples::~OsdUniformSamples() = default;

void OsdUniformSamples::prepareBfr() {
  Bfr& b = *bfr_;
  if (!b.surfaces.empty()) return;
  const int faceCount = faces();
  b.surfaces.resize(faceCount);
  b.patchPointOffsets.assign(1, 0);
  for (int f = 0; f < faceCount; ++f) {
    size_t floats = 0;
    if (faceOffsets_[f + 1] > faceOffsets_[f]) {
      if (!b.factory->InitVertexSurface(f, &b.surfaces[f])) {
        throw std::runtime_error("Bfr has no surface for face " + std::to_string(f));
      }
      floats = size_t(b.surfaces[f].GetNumPatchPoints()) * 3;
    }
    b.patchPointOffsets.push_back(b.patchPointOffsets.back() + floats);
  }
  b.patchPoints.resize(b.patchPointOffsets.back());
  b.uv.resize(2 * samples());
  for (int f = 0; f < faceCount; ++f) {
    if (faceOffsets_[f + 1] == faceOffsets_[f]) continue;
    const Surface& s = b.surfaces[f];
    s.PreparePatchPoints(meshPoints_.data(), 3, b.patchPoints.data() + b.patchPointOffsets[f], 3);
    OsdBfr::Tessellation(s.GetParameterization(), rate_).GetCoords(b.uv.data() + 2 * faceOffsets_[f]);
  }
}

void OsdUniformSamples::evaluateBfrPrepared(float* out) const {
  const Bfr& b = *bfr_;
  tbb::parallel_for(tbb::blocked_range<int>(0, faces(), 16), [&](const tbb::blocked_range<int>& range) {
    for (int f = range.begin(); f != range.end(); ++f) {
      const Surface& s = b.surfaces[f];
      const float* points = b.patchPoints.data() + b.patchPointOffsets[f];
      for (size_t i = faceOffsets_[f]; i < faceOffsets_[f + 1]; ++i) {
        s.Evaluate(b.uv.data() + 2 * i, points, 3, out + 3 * i);
      }
    }
  });
}

void OsdUniformSamples::evaluateBfrPerFace(float* out) const {
  struct Scratch {
    Surface surface;
    std::vector<float> patchPoints, uv;
  };
  tbb::enumerable_thread_specific<Scratch> scratch;
  const Bfr& b = *bfr_;
  tbb::parallel_for(tbb::blocked_range<int>(0, faces(), 16), [&](const tbb::blocked_range<int>& range) {
    Scratch& local = scratch.local();
    for (int f = range.begin(); f != range.end(); ++f) {
      if (faceOffsets_[f + 1] == faceOffsets_[f]) continue;
      if (!b.factory->InitVertexSurface(f, &local.surface)) continue;
      local.patchPoints.resize(size_t(local.surface.GetNumPatchPoints()) * 3);
      local.surface.PreparePatchPoints(meshPoints_.data(), 3, local.patchPoints.data(), 3);
      OsdBfr::Tessellation tessellation(local.surface.GetParameterization(), rate_);
      local.uv.resize(2 * size_t(tessellation.GetNumCoords()));
      tessellation.GetCoords(local.uv.data());
      float* faceOut = out + 3 * faceOffsets_[f];
      for (int i = 0; i < tessellation.GetNumCoords(); ++i) {
        local.surface.Evaluate(local.uv.data() + 2 * i, local.patchPoints.data(), 3, faceOut + 3 * i);
      }
    }
  });
}

void OsdUniformSamples::prepareOsdEval(double& stencilMs) {
  if (eval_) return;
  auto e = std::make_unique<Eval>();
  e->refiner = createTopologyRefiner(mesh_);
  Far::PatchTableFactory::Options options = patchOptions(mesh_);
  auto adaptive = options.GetRefineAdaptiveOptions();
  adaptive.SetSecondaryLevel(2);
  e->refiner->RefineAdaptive(adaptive);

  Far::StencilTableFactory::Options stencilOptions;
  stencilOptions.generateOffsets = true;
  stencilOptions.generateIntermediateLevels = true;
  std::unique_ptr<const Far::StencilTable> refined(Far::StencilTableFactory::Create(*e->refiner, stencilOptions));
  e->table.reset(Far::PatchTableFactory::Create(*e->refiner, options));
  std::unique_ptr<const Far::StencilTable> all;
  if (const Far::StencilTable* local = e->table->GetLocalPointStencilTable()) {
    all.reset(Far::StencilTableFactory::AppendLocalPointStencilTable(*e->refiner, refined.get(), local));
  }
  const Far::StencilTable& stencils = all ? *all : *refined;
  const int coarse = e->refiner->GetLevel(0).GetNumVertices();
  e->points.resize(size_t(coarse) + stencils.GetNumStencils());
  for (int v = 0; v < coarse; ++v) {
    for (int k = 0; k < 3; ++k) e->points[v].p[k] = meshPoints_[3 * v + k];
  }
  auto start = std::chrono::steady_clock::now();
  stencils.UpdateValues(e->points.data(), e->points.data() + coarse);
  stencilMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  e->cpuTable = Osd::CpuPatchTable::Create(e->table.get());

  // PatchCoords at exactly Bfr's (u,v): n-gon coordinates go to their normalized sub-face, which
  // is a Ptex face of Far's.
  Far::PatchMap map(*e->table);
  Far::PtexIndices ptex(*e->refiner);
  e->coords.resize(samples());
  std::vector<float> uv;
  for (int f = 0; f < faces(); ++f) {
    if (faceOffsets_[f + 1] == faceOffsets_[f]) continue;
    OsdBfr::Parameterization parameterization = faceParameterization(mesh_.faceSizes[f]);
    OsdBfr::Tessellation tessellation(parameterization, rate_);
    uv.resize(2 * size_t(tessellation.GetNumCoords()));
    tessellation.GetCoords(uv.data());
    for (int i = 0; i < tessellation.GetNumCoords(); ++i) {
      float st[2] = {uv[2 * i], uv[2 * i + 1]};
      int ptexFace = ptex.GetFaceId(f);
      if (parameterization.HasSubFaces()) ptexFace += parameterization.ConvertCoordToNormalizedSubFace(uv.data() + 2 * i, st);
      const Far::PatchTable::PatchHandle* handle = map.FindPatch(ptexFace, st[0], st[1]);
      if (handle == nullptr) throw std::runtime_error("Far::PatchMap finds no patch in face " + std::to_string(f));
      e->coords[faceOffsets_[f] + i] = Osd::PatchCoord(*handle, st[0], st[1]);
    }
  }
  eval_ = std::move(e);
}

void OsdUniformSamples::evaluateOsdEval(float* out) const {
  const Eval& e = *eval_;
  Osd::BufferDescriptor srcDesc(0, 3, 3), dstDesc(0, 3, 3);
  Osd::OmpEvaluator::EvalPatches(&e.points[0].p[0], srcDesc, out, dstDesc, int(e.coords.size()), e.coords.data(),
                                 e.cpuTable->GetPatchArrayBuffer(), e.cpuTable->GetPatchIndexBuffer(),
                                 e.cpuTable->GetPatchParamBuffer());
}

const float* OsdUniformSamples::uv(size_t i) const { return bfr_->uv.data() + 2 * i; }

double OsdUniformSamples::maxDeviationFromBfr(const float* out, int faceStride) const {
  const Bfr& b = *bfr_;
  double worst = 0;
  for (int f = 0; f < faces(); f += faceStride) {
    const float* points = b.patchPoints.data() + b.patchPointOffsets[f];
    for (size_t i = faceOffsets_[f]; i < faceOffsets_[f + 1]; ++i) {
      float p[3];
      b.surfaces[f].Evaluate(b.uv.data() + 2 * i, points, 3, p);
      double d2 = 0;
      for (int k = 0; k < 3; ++k) d2 += double(p[k] - out[3 * i + k]) * double(p[k] - out[3 * i + k]);
      worst = std::max(worst, std::sqrt(d2));
    }
  }
  return worst;
}

size_t OsdUniformSamples::patchCount() const { return eval_ ? size_t(eval_->table->GetNumPatchesTotal()) : 0; }

}  // namespace tessera::bench
