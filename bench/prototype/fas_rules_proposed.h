// PROTOTYPE, not built into the library: the FAS step of core/fas_rules.h (as of commit 1bd4bff,
// written with the CER recovering/locating operators of core/cer_layout.h) with the changes
// proposed in bench/RESULTS.md, so that tessera-bench can measure them beside the library.
// Every output is computed from the same operands in the same order as core/fas_rules.h, so the
// results are bit-identical (tessera-bench checks this before timing).
//
// PROPOSED 1 (StepProgram): run the recovering and locating operators once per ring shape, not
// once per point of every block at every level. refineRingBlocks refines thousands of blocks of
// one shape; decoding vertex_f/vertex_e/face_e/vertex_v/face_v/locate_* (8- or 16-bit unpacking,
// divisions, `% sectors`) cost about as many instructions as the arithmetic itself. The decoded
// step is ~(12n+1) small records (about 1 KB at n = 10) that stay in L1. CUDA keeps decoding per
// point, where the ALU is idle anyway (paper §4.1).
// PROPOSED 2: __restrict__ on the stencil helpers (no run-time overlap checks around each loop).
// PROPOSED 3: the smooth EV rule sums sector by sector with the lanes innermost (vectorised).
#pragma once

#include <cstdint>
#include <vector>

#include "core/fas_rules.h"

// A second translation unit compiles these templates for another instruction set under another
// namespace name (fas_proposed_avx512.cpp), so the linker never merges the two instantiations.
#ifndef TESSERA_PROPOSED_NS
#define TESSERA_PROPOSED_NS proposed
#endif

namespace tessera::TESSERA_PROPOSED_NS {

#define TESSERA_RESTRICT __restrict__

// The decoded step for blocks of W floats per point: float offsets (point index × W, so each
// operand is one load plus an addressing mode), `in` = the ring being refined, `out` = the
// refined set being written.
struct StepProgram {
  struct Average4In {  // face point: four ring points
    uint32_t out, a, b, c, d;
  };
  struct EdgeSmooth {  // (v0 + v1 + f0 + f1) / 4, v from in, f from out
    uint32_t out, v0, v1, f0, f1;
  };
  struct EdgeSharp {  // midpoint of two ring points
    uint32_t out, v0, v1;
  };
  struct VertexSmooth {  // valence-4 rule: v and n from in, f from out
    uint32_t out, v, n[4], f[4];
  };
  struct VertexCrease {  // 3/4 v + 1/8 (n0 + n1), all from in
    uint32_t out, v, n0, n1;
  };
  std::vector<Average4In> faces;
  std::vector<EdgeSmooth> smoothEdges;
  std::vector<EdgeSharp> sharpEdges;
  std::vector<VertexSmooth> smoothVertices;
  std::vector<VertexCrease> creaseVertices;
};

// Decodes the step exactly as refineSectorFaces/refineSpoke/refineSectorInterior walk it.
template <int W>
inline StepProgram decodeStep(const RingRules& rules) {
  using namespace cer;
  const RingShape& shape = rules.shape;
  StepProgram program;
  auto offset = [](int index) { return uint32_t(index) * W; };
  for (int f = 0; f < 4 * shape.sectors; ++f) {
    PackedIndices v = vertexF(shape, f);
    program.faces.push_back(
        {offset(locateF(shape, f)), offset(v[0]), offset(v[1]), offset(v[2]), offset(v[3])});
  }
  auto edge = [&](int e, bool sharp) {
    PackedIndices v = vertexE(shape, e);
    if (sharp) {
      program.sharpEdges.push_back({offset(locateE(shape, e)), offset(v[0]), offset(v[1])});
      return;
    }
    PackedIndices f = faceE(shape, e);
    program.smoothEdges.push_back({offset(locateE(shape, e)), offset(v[0]), offset(v[1]),
                                   offset(locateF(shape, f[0])), offset(locateF(shape, f[1]))});
  };
  auto vertex = [&](int j, bool sharp) {
    PackedIndices n = vertexV(shape, j);
    uint32_t out = offset(locateV(shape, j)), v = offset(ringIndexOfVertex(j));
    if (sharp) {
      program.creaseVertices.push_back({out, v, offset(n[0]), offset(n[1])});
      return;
    }
    PackedIndices f = faceV(shape, j);
    program.smoothVertices.push_back(
        {out,
         v,
         {offset(n[0]), offset(n[1]), offset(n[2]), offset(n[3])},
         {offset(locateF(shape, f[0])), offset(locateF(shape, f[1])), offset(locateF(shape, f[2])),
          offset(locateF(shape, f[3]))}});
  };
  for (int j = 0; j < shape.spokeCount(); ++j) {
    const bool sharp = rules.spokeSharp(j);
    edge(6 * j, sharp);
    edge(6 * j + 1, sharp);
    vertex(1 + 2 * j, sharp);
  }
  for (int i = 0; i < shape.sectors; ++i) {
    for (int e = 6 * i + 2; e < 6 * i + 6; ++e) edge(e, false);
    vertex(2 + 2 * i, false);
  }
  return program;
}

namespace fas_detail {

template <int W>
inline void average4(float* TESSERA_RESTRICT out, const float* TESSERA_RESTRICT a,
                     const float* TESSERA_RESTRICT b, const float* TESSERA_RESTRICT c,
                     const float* TESSERA_RESTRICT d) {
  for (int k = 0; k < W; ++k) out[k] = 0.25f * ((a[k] + b[k]) + (c[k] + d[k]));
}

template <int W>
inline void midpoint(float* TESSERA_RESTRICT out, const float* TESSERA_RESTRICT a,
                     const float* TESSERA_RESTRICT b) {
  for (int k = 0; k < W; ++k) out[k] = 0.5f * (a[k] + b[k]);
}

template <int W>
inline void creaseVertex(float* TESSERA_RESTRICT out, const float* TESSERA_RESTRICT v,
                         const float* TESSERA_RESTRICT a, const float* TESSERA_RESTRICT b) {
  for (int k = 0; k < W; ++k) out[k] = 0.75f * v[k] + 0.125f * (a[k] + b[k]);
}

template <int W>
inline void regularVertex(float* TESSERA_RESTRICT out, const float* TESSERA_RESTRICT v,
                          const float* TESSERA_RESTRICT n0, const float* TESSERA_RESTRICT n1,
                          const float* TESSERA_RESTRICT n2, const float* TESSERA_RESTRICT n3,
                          const float* TESSERA_RESTRICT f0, const float* TESSERA_RESTRICT f1,
                          const float* TESSERA_RESTRICT f2, const float* TESSERA_RESTRICT f3) {
  for (int k = 0; k < W; ++k) {
    float edges = (n0[k] + n1[k]) + (n2[k] + n3[k]);
    float faces = (f0[k] + f1[k]) + (f2[k] + f3[k]);
    out[k] = 0.5f * v[k] + 0.0625f * (edges + faces);
  }
}

}  // namespace fas_detail

// The EV rule of core/fas_rules.h with the smooth sum reordered (PROPOSED 3); same per-lane order.
template <int W>
inline void refineExtraordinaryVertex(const RingRules& rules, const float* in, float* out) {
  using namespace cer;
  const int n = rules.shape.sectors;
  if (rules.evRule == EvRule::kCorner) {
    for (int k = 0; k < W; ++k) out[k] = in[k];
  } else if (rules.evRule == EvRule::kCrease) {
    fas_detail::creaseVertex<W>(out, in, in + ringIndex(rules.creaseSpokeA, kE) * W,
                                in + ringIndex(rules.creaseSpokeB, kE) * W);
  } else {
    const float selfWeight = float(n - 2) / float(n);
    const float ringWeight = 1.0f / float(n * n);
    float sum[W];
    for (int k = 0; k < W; ++k) sum[k] = 0;
    for (int i = 0; i < n; ++i) {
      const float* e = in + ringIndex(i, kE) * W;
      const float* face = out + ringIndex(i, kD) * W;
      for (int k = 0; k < W; ++k) sum[k] += e[k] + face[k];
    }
    for (int k = 0; k < W; ++k) out[k] = selfWeight * in[k] + ringWeight * sum[k];
  }
}

// One step for one block: faces first (everything else reads them), then edges and vertices.
template <int W>
inline void refineRingStep(const RingRules& rules, const StepProgram& program, const float* in,
                           float* out) {
  using namespace fas_detail;
  for (const auto& s : program.faces)
    average4<W>(out + s.out, in + s.a, in + s.b, in + s.c, in + s.d);
  for (const auto& s : program.smoothEdges) {
    average4<W>(out + s.out, in + s.v0, in + s.v1, out + s.f0, out + s.f1);
  }
  for (const auto& s : program.sharpEdges) midpoint<W>(out + s.out, in + s.v0, in + s.v1);
  for (const auto& s : program.smoothVertices) {
    regularVertex<W>(out + s.out, in + s.v, in + s.n[0], in + s.n[1], in + s.n[2], in + s.n[3],
                     out + s.f[0], out + s.f[1], out + s.f[2], out + s.f[3]);
  }
  for (const auto& s : program.creaseVertices) {
    creaseVertex<W>(out + s.out, in + s.v, in + s.n0, in + s.n1);
  }
  TESSERA_PROPOSED_NS::refineExtraordinaryVertex<W>(rules, in, out);
}

}  // namespace tessera::TESSERA_PROPOSED_NS
