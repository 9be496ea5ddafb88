#include "bench/osd_ring_stencils.h"

#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/osd/bufferDescriptor.h>
#include <opensubdiv/osd/ompEvaluator.h>

#include <algorithm>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>

#include "bench/ring_workload.h"
#include "core/topology/far_topology.h"
#include "core/topology/lattice_walker.h"

namespace tessera::bench {

namespace {

namespace Osd = OpenSubdiv::Osd;

// Far's vertices of the CER refined set at every level, in CER order, chained from the base EV
// and its first spoke the way reference/far_reference.cpp's farRingLevel does (which returns
// positions; the stencils need the vertex indices themselves).
std::vector<std::vector<Index>> refinedSetVertices(const Far::TopologyRefiner& refiner,
                                                   const cer::RingShape& shape, int depth) {
  std::vector<std::vector<Index>> levels;
  Index ev = 0, spoke = cer::ringIndex(0, cer::kE);
  for (int level = 1; level <= depth; ++level) {
    const auto& parent = refiner.GetLevel(level - 1);
    Index childEv = parent.GetVertexChildVertex(ev);
    Index childSpoke = parent.GetEdgeChildVertex(parent.FindEdge(ev, spoke));
    LatticeWalker walker(refiner.GetLevel(level));
    auto sectors = walker.sectorsAround(childEv, childSpoke);
    if (!sectors)
      throw std::runtime_error("no quad fan around the EV at level " + std::to_string(level));
    std::vector<Index> vertices = walker.gather(*sectors, 3);
    bool complete = int(vertices.size()) == shape.refinedPointCount() &&
                    std::none_of(vertices.begin(), vertices.end(), [](Index v) { return v < 0; });
    if (!complete)
      throw std::runtime_error("incomplete refined set at level " + std::to_string(level));
    levels.push_back(std::move(vertices));
    ev = childEv;
    spoke = childSpoke;
  }
  return levels;
}

}  // namespace

RingStencils buildRingStencils(const ControlMesh& mesh, const cer::RingShape& shape, int depth) {
  std::unique_ptr<Far::TopologyRefiner> refiner = createTopologyRefiner(mesh);
  Far::TopologyRefiner::UniformOptions uniform(depth);
  uniform.fullTopologyInLastLevel = true;  // the lattice walk needs the last level's edges
  refiner->RefineUniform(uniform);

  Far::StencilTableFactory::Options options;
  options.interpolationMode = Far::StencilTableFactory::INTERPOLATE_VERTEX;
  options.generateOffsets = true;
  options.generateControlVerts = false;
  options.generateIntermediateLevels = true;
  options.factorizeIntermediateLevels = true;  // every stencil reads control points only
  options.maxLevel = depth;
  std::unique_ptr<const Far::StencilTable> table(
      Far::StencilTableFactory::Create(*refiner, options));

  // Without control-vertex stencils, level L's vertex v is stencil v + (vertices of levels 1..L-1).
  std::vector<int> levelFirst(depth + 2, 0);
  for (int level = 1; level <= depth; ++level) {
    levelFirst[level + 1] = levelFirst[level] + refiner->GetLevel(level).GetNumVertices();
  }
  if (table->GetNumStencils() != levelFirst[depth + 1] ||
      table->GetNumControlVertices() != shape.ringPointCount()) {
    throw std::runtime_error("unexpected stencil table shape");
  }

  RingStencils stencils;
  stencils.controlPoints = table->GetNumControlVertices();
  auto levels = refinedSetVertices(*refiner, shape, depth);
  for (int level = 1; level <= depth; ++level) {
    for (Index v : levels[level - 1]) {
      Far::Stencil stencil = table->GetStencil(levelFirst[level] + v);
      stencils.sizes.push_back(stencil.GetSize());
      stencils.offsets.push_back(int(stencils.indices.size()));
      stencils.indices.insert(stencils.indices.end(), stencil.GetVertexIndices(),
                              stencil.GetVertexIndices() + stencil.GetSize());
      stencils.weights.insert(stencils.weights.end(), stencil.GetWeights(),
                              stencil.GetWeights() + stencil.GetSize());
    }
  }
  stencils.refinedPoint.resize(stencils.count());
  std::iota(stencils.refinedPoint.begin(), stencils.refinedPoint.end(), 0);
  return stencils;
}

RingStencils balanceForStaticSchedule(const RingStencils& stencils, int threads) {
  // libgomp's static split of S iterations: the first S % T threads take one extra.
  const int count = stencils.count();
  std::vector<int> capacity(threads, count / threads);
  for (int t = 0; t < count % threads; ++t) ++capacity[t];
  // Longest stencils first, each to the thread with the fewest weights that still has room.
  std::vector<int> bySize(count);
  std::iota(bySize.begin(), bySize.end(), 0);
  std::stable_sort(bySize.begin(), bySize.end(),
                   [&](int a, int b) { return stencils.sizes[a] > stencils.sizes[b]; });
  std::vector<std::vector<int>> runs(threads);
  std::vector<long> weights(threads, 0);
  for (int s : bySize) {
    int best = -1;
    for (int t = 0; t < threads; ++t) {
      if (int(runs[t].size()) < capacity[t] && (best < 0 || weights[t] < weights[best])) best = t;
    }
    runs[best].push_back(s);
    weights[best] += stencils.sizes[s];
  }
  RingStencils balanced;
  balanced.controlPoints = stencils.controlPoints;
  for (auto& run : runs) {
    std::sort(run.begin(), run.end());  // level order within a run: results land in order
    for (int s : run) {
      const int offset = stencils.offsets[s], size = stencils.sizes[s];
      balanced.sizes.push_back(size);
      balanced.offsets.push_back(int(balanced.indices.size()));
      balanced.indices.insert(balanced.indices.end(), stencils.indices.begin() + offset,
                              stencils.indices.begin() + offset + size);
      balanced.weights.insert(balanced.weights.end(), stencils.weights.begin() + offset,
                              stencils.weights.begin() + offset + size);
      balanced.refinedPoint.push_back(stencils.refinedPoint[s]);
    }
  }
  return balanced;
}

size_t chunkedIndex(int points, int rings, int chunkRings, int ring, int point) {
  size_t firstRing = size_t(ring / chunkRings) * chunkRings;
  size_t chunk = std::min<size_t>(chunkRings, rings - firstRing);
  return firstRing * points * 3 + size_t(point) * 3 * chunk + (ring - firstRing) * 3;
}

void fillChunkedRings(const cer::RingShape& shape, const std::vector<float>& distinct, int rings,
                      int chunkRings, float* source) {
  const int points = shape.ringPointCount();
  for (int r = 0; r < rings; ++r) {
    const float* ring = distinct.data() + size_t(r % kDistinctRings) * points * 3;
    for (int p = 0; p < points; ++p) {
      float* out = source + chunkedIndex(points, rings, chunkRings, r, p);
      out[0] = ring[3 * p];
      out[1] = ring[3 * p + 1];
      out[2] = ring[3 * p + 2];
    }
  }
}

void evalChunkedStencils(const RingStencils& stencils, const float* source, float* result,
                         int rings, int chunkRings) {
  for (int firstRing = 0; firstRing < rings; firstRing += chunkRings) {
    const int chunk = std::min(chunkRings, rings - firstRing);
    Osd::BufferDescriptor descriptor(0, 3 * chunk, 3 * chunk);
    Osd::OmpEvaluator::EvalStencils(source + size_t(firstRing) * stencils.controlPoints * 3,
                                    descriptor, result + size_t(firstRing) * stencils.count() * 3,
                                    descriptor, stencils.sizes.data(), stencils.offsets.data(),
                                    stencils.indices.data(), stencils.weights.data(), 0,
                                    stencils.count());
  }
}

}  // namespace tessera::bench
