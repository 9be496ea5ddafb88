// The paper's Fig. 6 (depth estimation), Fig. 5 (the η split) and a tightness measurement
// (measured error / ε), registered by tess_bench.cpp after Table 2:
//
//   BM_DepthEstimate_Tessera/<model>/eta:<η>  core's estimateDepth per ring with budget ηε,
//       ε = 0.005 × the model's smallest bounding-box side; counters avg_depth, max_depth,
//       ns_per_ring (one thread).
//   BM_DepthEstimate_ControlMesh/<model>      the control-polyhedron bound of tess_depth.h with
//       the whole ε (and the plain convex-hull bound as avg_depth_hull).
//   BM_TessEta/<model>/<10η>                   tessellate() (plan + watertight mesh) at
//       ε = 1e-3 × the bounding-box diagonal; counters triangles, ring_triangles, avg_depth.
//   BM_TessEtaRings/<model>/<10η>              the same for the singularities only (the paper's
//       Fig. 5 measures those): the patch set without its regular patches.
//   BM_Tightness/<model>/<ε>                   one measurement per case (time meaningless):
//       max ‖mesh − limit‖ / ε over 7 points of up to 20K triangles, against Bfr (approximation
//       level 10) as tests/tessellation_test.cpp does.
#pragma once

#include <cstddef>
#include <vector>

#include "bench/tess_common.h"
#include "core/uniform/tessellation_plan.h"

namespace tessera::bench {

void registerDepthEstimates();
void registerEtaSweep();
void registerTightness();

// Table 2 accuracy checks against the limit surface from Bfr at approximation level 10 (exact
// down to Far level 10; deeper pieces are skipped), as distances relative to the diagonal.
// Tessera: corners and midpoints of ~400 pieces spread over the plan and of ~400 of its
// innermost (approximated) pieces; `innermost` gets the latter's maximum.
double sampledLimitDeviation(const LoadedModel& model, const TessellationPlan& plan,
                             const std::vector<size_t>& offsets, const Vec3* samples, double& innermost);
// OpenSubdiv (prepared Bfr's samples): every sample of every `faceStride`-th face.
class OsdUniformSamples;
double osdLimitDeviation(const LoadedModel& model, const OsdUniformSamples& osd, const float* samples,
                         int faceStride);

}  // namespace tessera::bench
