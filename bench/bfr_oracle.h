// OpenSubdiv Bfr at one uniform rate on every face: the baseline Tessera's user path is compared
// with at the oracle rate (oracle_rate.h). Positions, normals (from Evaluate's derivatives) and
// facets, per face on all cores (TBB), into buffers sized when the object is made. Faces keep
// their own copies of edge points (no watertight assembly) and nothing is encoded, which only
// favours Bfr. Used warm by tess_glb_bench.cpp, cold and across edits by cold_bench.cpp.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "core/mesh/control_mesh.h"

namespace tessera::bench {

class BfrOracle {
 public:
  // Far::TopologyRefiner from the mesh, a RefinerSurfaceFactory over it with an empty
  // thread-safe cache, each face's coordinates and facets at `rate` counted (holes have none)
  // and the output allocated.
  BfrOracle(const ControlMesh& mesh, int rate);
  ~BfrOracle();

  size_t triangles() const { return facetFirst_.back(); }
  size_t vertices() const { return vertexFirst_.back(); }

  // What Bfr's tutorials do per face: InitVertexSurface (through the factory's cache, which
  // persists from call to call), PreparePatchPoints from `points` (xyz per control vertex),
  // Tessellation at the rate, GetCoords, Evaluate with derivatives, GetFacets.
  void run(const float* points);

  // For animation, where only positions change: each face's Surface (topology only) and the
  // facets are made here once, so that runPrepared is left with the work new positions need.
  void prepareSurfaces();
  // After prepareSurfaces: PreparePatchPoints from `points`, GetCoords and Evaluate per face.
  void runPrepared(const float* points);

 private:
  struct Osd;
  int faceCount_ = 0;
  int rate_ = 0;
  std::unique_ptr<Osd> osd_;
  std::vector<size_t> vertexFirst_, facetFirst_;  // face f's output starts there; holes are empty
  std::vector<float> positions_, normals_;
  std::vector<int> indices_;
};

}  // namespace tessera::bench
