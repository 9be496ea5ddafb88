// One Catmull-Clark step on a CER ring (paper §4.2, rules of OpenSubdiv's Sdc, MATH.md §1).
//
// The step reads a ring (6n+1 points) and writes the refined set (12n+1 points) laid out as in
// cer_layout.h. Each point is a block of W floats: 3 coordinates × W/3 rings processed side by
// side (SIMD lanes on the CPU, W = 3 for one ring per CUDA warp). Every neighbour is found by
// index arithmetic; there are no connectivity tables.
//
// Supported ring kinds: smooth interior rings, rings whose spokes (the edges leaving the EV along
// sector x-axes) are infinitely sharp creases, open rings whose first and last spokes are
// boundary edges, and a corner EV. The caller guarantees the rest of the ring is smooth and
// regular (see patch_builder.cpp), which is what lets every emitted patch be a B-spline.
#pragma once

#include "core/base/host_device.h"
#include "core/rings/cer_layout.h"

namespace tessera {

enum class EvRule : uint8_t { kSmooth, kCrease, kCorner };

struct RingRules {
  cer::RingShape shape;
  const uint8_t* sharpSpokes = nullptr;  // shape.spokeCount() flags; nullptr: all smooth
  EvRule evRule = EvRule::kSmooth;
  int creaseSpokeA = 0, creaseSpokeB = 0;  // the two sharp spokes when evRule == kCrease

  TESSERA_HD bool spokeSharp(int spoke) const {
    if (shape.open && (spoke == 0 || spoke == shape.sectors)) return true;
    return sharpSpokes != nullptr && sharpSpokes[spoke] != 0;
  }
  TESSERA_HD int nextSector(int i) const { return shape.open ? i + 1 : (i + 1) % shape.sectors; }
  TESSERA_HD int prevSector(int i) const {
    return shape.open ? i - 1 : (i + shape.sectors - 1) % shape.sectors;
  }
};

// Sdc rule selection at the EV: count sharp spokes (0-1 smooth, 2 crease, 3+ corner).
inline RingRules makeRingRules(cer::RingShape shape, const uint8_t* sharpSpokes, bool cornerEv) {
  RingRules rules{shape, sharpSpokes, EvRule::kSmooth, 0, 0};
  int sharpCount = 0;
  for (int s = 0; s < shape.spokeCount(); ++s) {
    if (!rules.spokeSharp(s)) continue;
    (sharpCount == 0 ? rules.creaseSpokeA : rules.creaseSpokeB) = s;
    ++sharpCount;
  }
  if (cornerEv || sharpCount > 2) {
    rules.evRule = EvRule::kCorner;
  } else if (sharpCount == 2) {
    rules.evRule = EvRule::kCrease;
  }
  return rules;
}

namespace fas_detail {

template <int W, typename Real>
TESSERA_HD void average4(Real* out, const Real* a, const Real* b, const Real* c, const Real* d) {
  for (int k = 0; k < W; ++k) out[k] = Real(0.25) * ((a[k] + b[k]) + (c[k] + d[k]));
}

template <int W, typename Real>
TESSERA_HD void midpoint(Real* out, const Real* a, const Real* b) {
  for (int k = 0; k < W; ++k) out[k] = Real(0.5) * (a[k] + b[k]);
}

// Crease vertex rule: 3/4 v + 1/8 (a + b).
template <int W, typename Real>
TESSERA_HD void creaseVertex(Real* out, const Real* v, const Real* a, const Real* b) {
  for (int k = 0; k < W; ++k) out[k] = Real(0.75) * v[k] + Real(0.125) * (a[k] + b[k]);
}

// Smooth valence-4 vertex rule: v/2 + (sum of 4 neighbours)/16 + (sum of 4 face points)/16.
template <int W, typename Real>
TESSERA_HD void regularVertex(Real* out, const Real* v, const Real* const n[4],
                              const Real* const f[4]) {
  for (int k = 0; k < W; ++k) {
    Real edges = (n[0][k] + n[1][k]) + (n[2][k] + n[3][k]);
    Real faces = (f[0][k] + f[1][k]) + (f[2][k] + f[3][k]);
    out[k] = Real(0.5) * v[k] + Real(0.0625) * (edges + faces);
  }
}

}  // namespace fas_detail

// Pass 1: the four face points of sector i (centroids; vertex_f, locate_f).
template <int W, typename Real = float>
TESSERA_HD void refineSectorFaces(const RingRules& rules, int i, const Real* in, Real* out) {
  const auto& shape = rules.shape;
  for (int f = 4 * i; f < 4 * i + 4; ++f) {
    cer::PackedIndices v = cer::vertexF(shape, f);
    fas_detail::average4<W, Real>(out + cer::locateF(shape, f) * W, in + v[0] * W, in + v[1] * W,
                                  in + v[2] * W, in + v[3] * W);
  }
}

namespace fas_detail {

// Edge point of interior edge e: the midpoint when sharp, else (v0 + v1 + f0 + f1) / 4 with the
// new face points of its two faces (vertex_e, face_e, locate_e).
template <int W, typename Real>
TESSERA_HD void edgePoint(const RingRules& rules, int e, bool sharp, const Real* in, Real* out) {
  const auto& shape = rules.shape;
  cer::PackedIndices v = cer::vertexE(shape, e);
  Real* result = out + cer::locateE(shape, e) * W;
  if (sharp) {
    midpoint<W, Real>(result, in + v[0] * W, in + v[1] * W);
    return;
  }
  cer::PackedIndices f = cer::faceE(shape, e);
  average4<W, Real>(result, in + v[0] * W, in + v[1] * W, out + cer::locateF(shape, f[0]) * W,
                    out + cer::locateF(shape, f[1]) * W);
}

// Vertex point of a regular interior vertex j: the crease rule along its spoke when sharp, else
// the valence-4 smooth rule over its neighbours and new face points (vertex_v, face_v, locate_v).
template <int W, typename Real>
TESSERA_HD void vertexPoint(const RingRules& rules, int j, bool sharp, const Real* in, Real* out) {
  const auto& shape = rules.shape;
  cer::PackedIndices n = cer::vertexV(shape, j);
  Real* result = out + cer::locateV(shape, j) * W;
  const Real* v = in + cer::ringIndexOfVertex(j) * W;
  if (sharp) {
    creaseVertex<W, Real>(result, v, in + n[0] * W, in + n[1] * W);
    return;
  }
  cer::PackedIndices f = cer::faceV(shape, j);
  const Real* neighbours[4] = {in + n[0] * W, in + n[1] * W, in + n[2] * W, in + n[3] * W};
  const Real* faces[4] = {out + cer::locateF(shape, f[0]) * W, out + cer::locateF(shape, f[1]) * W,
                          out + cer::locateF(shape, f[2]) * W, out + cer::locateF(shape, f[3]) * W};
  regularVertex<W, Real>(result, v, neighbours, faces);
}

}  // namespace fas_detail

// Pass 2 for spoke j (sector j's x-axis): its two edge points and the vertex point of e_j.
// Needs the face points of sectors j and j-1 from pass 1.
template <int W, typename Real = float>
TESSERA_HD void refineSpoke(const RingRules& rules, int j, const Real* in, Real* out) {
  const bool sharp = rules.spokeSharp(j);
  fas_detail::edgePoint<W, Real>(rules, 6 * j, sharp, in, out);
  fas_detail::edgePoint<W, Real>(rules, 6 * j + 1, sharp, in, out);
  fas_detail::vertexPoint<W, Real>(rules, 1 + 2 * j, sharp, in, out);
}

// Pass 2 for sector i: its four non-spoke edge points and the vertex point of d_i.
template <int W, typename Real = float>
TESSERA_HD void refineSectorInterior(const RingRules& rules, int i, const Real* in, Real* out) {
  for (int e = 6 * i + 2; e < 6 * i + 6; ++e) fas_detail::edgePoint<W, Real>(rules, e, false, in, out);
  fas_detail::vertexPoint<W, Real>(rules, 2 + 2 * i, false, in, out);
}

// Pass 2 for the EV itself (after all face points exist).
template <int W, typename Real = float>
TESSERA_HD void refineExtraordinaryVertex(const RingRules& rules, const Real* in, Real* out) {
  using namespace cer;
  const int n = rules.shape.sectors;
  Real* result = out;
  const Real* ev = in;
  if (rules.evRule == EvRule::kCorner) {
    for (int k = 0; k < W; ++k) result[k] = ev[k];
  } else if (rules.evRule == EvRule::kCrease) {
    fas_detail::creaseVertex<W, Real>(result, ev, in + ringIndex(rules.creaseSpokeA, kE) * W,
                                in + ringIndex(rules.creaseSpokeB, kE) * W);
  } else {
    // ((n-2)/n) v + (1/n^2) (sum of edge neighbours + sum of face points)
    const Real selfWeight = Real(n - 2) / Real(n);
    const Real ringWeight = Real(1) / Real(n * n);
    for (int k = 0; k < W; ++k) {
      Real sum = 0;
      for (int i = 0; i < n; ++i) {
        sum += in[ringIndex(i, kE) * W + k] + out[ringIndex(i, kD) * W + k];
      }
      result[k] = selfWeight * ev[k] + ringWeight * sum;
    }
  }
}

// The whole step for one ring block, sequentially (the CPU path; CUDA spreads the loops over a warp).
template <int W, typename Real = float>
TESSERA_HD void refineRingStep(const RingRules& rules, const Real* in, Real* out) {
  const int n = rules.shape.sectors;
  for (int i = 0; i < n; ++i) refineSectorFaces<W, Real>(rules, i, in, out);
  for (int j = 0; j < rules.shape.spokeCount(); ++j) refineSpoke<W, Real>(rules, j, in, out);
  for (int i = 0; i < n; ++i) refineSectorInterior<W, Real>(rules, i, in, out);
  refineExtraordinaryVertex<W, Real>(rules, in, out);
}

}  // namespace tessera
