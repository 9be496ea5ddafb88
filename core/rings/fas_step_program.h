// One CER refinement step (fas_rules.h) decoded for a ring shape: the operands of every refined
// point as offsets into the ring block and the refined block (CPU block path of fas.cpp, and the
// CUDA kernel through gpu/cuda/warp_step_program.h).
//
// refineRingBlocks refines thousands of blocks of one shape level by level. Running the
// recovering and locating operators of cer_layout.h for every point of every block at every
// level cost about as many instructions as the stencils themselves (8/16-bit unpacking, `/4`,
// `/6`, `% sectors`, switches; bench/RESULTS.md "Profile"). They depend on the shape alone, so
// they run once per call here and the kernel only reads this table (about 3 KB at n = 10, in
// L1). The operators stay the single source of connectivity. The CUDA kernel first called them
// per point (paper §4.1); on an H200 that made it issue-bound, and it reads this table too.
#pragma once

#include <cstdint>
#include <vector>

#include "core/rings/fas_rules.h"

namespace tessera {

// Offsets are point index × the floats of one point, so each operand is one load.
// `in`: the ring being refined; `out`: the refined set being written (face points are read
// back from it by the edge and vertex rules).
struct StepProgram {
  struct Face {  // centroid of four ring points
    uint32_t out, a, b, c, d;
  };
  struct SmoothEdge {  // (v0 + v1 + f0 + f1) / 4: v from in, f from out
    uint32_t out, v0, v1, f0, f1;
  };
  struct SharpEdge {  // midpoint of two ring points
    uint32_t out, v0, v1;
  };
  struct SmoothVertex {  // valence-4 rule: v and n from in, f from out
    uint32_t out, v, n[4], f[4];
  };
  struct CreaseVertex {  // 3/4 v + 1/8 (n0 + n1), all from in
    uint32_t out, v, n0, n1;
  };
  struct EvTerm {  // one sector's share of the smooth EV rule: e_i from in, its face point from out
    uint32_t edge, face;
  };

  std::vector<Face> faces;
  std::vector<SmoothEdge> smoothEdges;
  std::vector<SharpEdge> sharpEdges;
  std::vector<SmoothVertex> smoothVertices;
  std::vector<CreaseVertex> creaseVertices;

  // The EV (point 0 of both sets) by the rule makeRingRules chose.
  EvRule evRule = EvRule::kSmooth;
  uint32_t evCreaseA = 0, evCreaseB = 0;     // kCrease: the two sharp spokes' e points
  std::vector<EvTerm> evTerms;               // kSmooth: sectors in order
  float evSelfWeight = 0, evRingWeight = 0;  // kSmooth: (n-2)/n and 1/n²
};

// Walks the step exactly as refineSectorFaces, refineSpoke, refineSectorInterior and
// refineExtraordinaryVertex do, for points of `pointFloats` floats.
StepProgram decodeStep(const RingRules& rules, int pointFloats);

}  // namespace tessera
