// OpenSubdiv producing the samples of the paper's Table 2 (uniform tessellation level p per base
// face), the baselines of tess_bench.cpp. Every face's (u,v) come from Bfr::Tessellation at
// uniform rate p: (p+1)² for quads, Bfr's own parameterization (quad sub-faces) for n-gons.
// Three ways to evaluate them, all on both cores:
//  - Bfr, prepared: Bfr::Surface and patch points of every face built in setup, the (u,v)
//    computed in setup; only Surface::Evaluate is timed.
//  - Bfr, per face: the whole per-face work Bfr's tutorials do (InitVertexSurface with a
//    thread-safe cache that persists between iterations, PreparePatchPoints, Tessellation,
//    GetCoords, Evaluate).
//  - Far::PatchTable (adaptive, Tessera's isolation options, Gregory basis end caps) with
//    Osd::OmpEvaluator::EvalPatches on PatchCoords built in setup with Far::PatchMap; the
//    refined and end-cap points are computed in setup (Tessera's patch set holds refined points
//    too), so only EvalPatches is timed.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "core/mesh/control_mesh.h"

namespace tessera::bench {

class OsdUniformSamples {
 public:
  OsdUniformSamples(const ControlMesh& mesh, int rate);
  ~OsdUniformSamples();

  size_t samples() const { return faceOffsets_.back(); }
  int faces() const { return int(faceOffsets_.size()) - 1; }

  // Bfr with everything but Surface::Evaluate done here.
  void prepareBfr();
  void evaluateBfrPrepared(float* out) const;
  // Bfr doing all of its per-face work inside the call.
  void evaluateBfrPerFace(float* out) const;

  // Far::PatchTable + PatchCoords + refined points; `stencilMs` is what updating the refined and
  // end-cap points from the control points took once, on one thread (not part of any timing).
  void prepareOsdEval(double& stencilMs);
  void evaluateOsdEval(float* out) const;
  size_t patchCount() const;

  // Prepared Bfr's samples of face f are [faceBegin(f), faceBegin(f + 1)), at parameters uv(i)
  // of Bfr's parameterization of the face (needs prepareBfr).
  size_t faceBegin(int f) const { return faceOffsets_[f]; }
  const float* uv(size_t i) const;

  // Largest distance between `out` and prepared Bfr on every `faceStride`-th face (needs
  // prepareBfr): checks that two methods produced the same samples.
  double maxDeviationFromBfr(const float* out, int faceStride) const;

 private:
  struct Bfr;
  struct Eval;
  const ControlMesh& mesh_;
  int rate_;
  std::vector<size_t> faceOffsets_;  // samples of face f start at faceOffsets_[f]
  std::vector<float> meshPoints_;    // xyz per control vertex
  std::unique_ptr<Bfr> bfr_;
  std::unique_ptr<Eval> eval_;
};

}  // namespace tessera::bench
