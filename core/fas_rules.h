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

#include "core/cer_layout.h"
#include "core/host_device.h"

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

template <int W>
TESSERA_HD void average4(float* out, const float* a, const float* b, const float* c,
                         const float* d) {
  for (int k = 0; k < W; ++k) out[k] = 0.25f * ((a[k] + b[k]) + (c[k] + d[k]));
}

template <int W>
TESSERA_HD void midpoint(float* out, const float* a, const float* b) {
  for (int k = 0; k < W; ++k) out[k] = 0.5f * (a[k] + b[k]);
}

// Crease vertex rule: 3/4 v + 1/8 (a + b).
template <int W>
TESSERA_HD void creaseVertex(float* out, const float* v, const float* a, const float* b) {
  for (int k = 0; k < W; ++k) out[k] = 0.75f * v[k] + 0.125f * (a[k] + b[k]);
}

// Smooth valence-4 vertex rule: v/2 + (sum of 4 neighbours)/16 + (sum of 4 face points)/16.
template <int W>
TESSERA_HD void regularVertex(float* out, const float* v, const float* const n[4],
                              const float* const f[4]) {
  for (int k = 0; k < W; ++k) {
    float edges = (n[0][k] + n[1][k]) + (n[2][k] + n[3][k]);
    float faces = (f[0][k] + f[1][k]) + (f[2][k] + f[3][k]);
    out[k] = 0.5f * v[k] + 0.0625f * (edges + faces);
  }
}

}  // namespace fas_detail

// Pass 1: the four face points of sector i.
template <int W>
TESSERA_HD void refineSectorFaces(const RingRules& rules, int i, const float* in, float* out) {
  using namespace cer;
  const auto& shape = rules.shape;
  auto P = [&](int index) { return in + index * W; };
  int next = rules.nextSector(i);
  const float* ev = P(0);
  const float* e = P(ringIndex(i, kE));
  const float* a = P(ringIndex(i, kA));
  const float* d = P(ringIndex(i, kD));
  const float* r21 = P(ringIndex(i, kD21));
  const float* r22 = P(ringIndex(i, kD22));
  const float* r12 = P(ringIndex(i, kD12));
  const float* eNext = P(ringIndex(next, kE));
  const float* aNext = P(ringIndex(next, kA));
  fas_detail::average4<W>(out + ringIndex(i, kD) * W, ev, e, d, eNext);
  fas_detail::average4<W>(out + extraIndex(shape, i, kX31) * W, e, a, r21, d);
  fas_detail::average4<W>(out + extraIndex(shape, i, kX33) * W, d, r21, r22, r12);
  fas_detail::average4<W>(out + extraIndex(shape, i, kX13) * W, eNext, d, r12, aNext);
}

// Pass 2 for spoke j (sector j's x-axis): its two edge points and the vertex point of e_j.
// Needs the face points of sectors j and j-1 from pass 1.
template <int W>
TESSERA_HD void refineSpoke(const RingRules& rules, int j, const float* in, float* out) {
  using namespace cer;
  const auto& shape = rules.shape;
  auto P = [&](int index) { return in + index * W; };
  auto Q = [&](int index) { return out + index * W; };
  const float* ev = P(0);
  const float* e = P(ringIndex(j, kE));
  const float* a = P(ringIndex(j, kA));
  float* innerEdge = Q(ringIndex(j, kE));
  float* outerEdge = Q(extraIndex(shape, j, kX30));
  float* vertex = Q(ringIndex(j, kA));
  if (rules.spokeSharp(j)) {
    fas_detail::midpoint<W>(innerEdge, ev, e);
    fas_detail::midpoint<W>(outerEdge, e, a);
    fas_detail::creaseVertex<W>(vertex, e, ev, a);
    return;
  }
  int prev = rules.prevSector(j);
  const float* face = Q(ringIndex(j, kD));
  const float* facePrev = Q(ringIndex(prev, kD));
  const float* outerFace = Q(extraIndex(shape, j, kX31));
  const float* outerFacePrev = Q(extraIndex(shape, prev, kX13));
  fas_detail::average4<W>(innerEdge, ev, e, face, facePrev);
  fas_detail::average4<W>(outerEdge, e, a, outerFace, outerFacePrev);
  const float* neighbours[4] = {ev, a, P(ringIndex(j, kD)), P(ringIndex(prev, kD))};
  const float* faces[4] = {face, outerFace, facePrev, outerFacePrev};
  fas_detail::regularVertex<W>(vertex, e, neighbours, faces);
}

// Pass 2 for sector i: its four non-spoke edge points and the vertex point of d_i.
template <int W>
TESSERA_HD void refineSectorInterior(const RingRules& rules, int i, const float* in, float* out) {
  using namespace cer;
  const auto& shape = rules.shape;
  auto P = [&](int index) { return in + index * W; };
  auto Q = [&](int index) { return out + index * W; };
  int next = rules.nextSector(i);
  const float* e = P(ringIndex(i, kE));
  const float* d = P(ringIndex(i, kD));
  const float* r21 = P(ringIndex(i, kD21));
  const float* r12 = P(ringIndex(i, kD12));
  const float* eNext = P(ringIndex(next, kE));
  const float* face = Q(ringIndex(i, kD));
  const float* f31 = Q(extraIndex(shape, i, kX31));
  const float* f33 = Q(extraIndex(shape, i, kX33));
  const float* f13 = Q(extraIndex(shape, i, kX13));
  fas_detail::average4<W>(Q(ringIndex(i, kD21)), e, d, face, f31);
  fas_detail::average4<W>(Q(extraIndex(shape, i, kX23)), d, r12, f13, f33);
  fas_detail::average4<W>(Q(ringIndex(i, kD12)), eNext, d, face, f13);
  fas_detail::average4<W>(Q(extraIndex(shape, i, kX32)), d, r21, f31, f33);
  const float* neighbours[4] = {e, eNext, r21, r12};
  const float* faces[4] = {face, f31, f33, f13};
  fas_detail::regularVertex<W>(Q(ringIndex(i, kD22)), d, neighbours, faces);
}

// Pass 2 for the EV itself (after all face points exist).
template <int W>
TESSERA_HD void refineExtraordinaryVertex(const RingRules& rules, const float* in, float* out) {
  using namespace cer;
  const int n = rules.shape.sectors;
  float* result = out;
  const float* ev = in;
  if (rules.evRule == EvRule::kCorner) {
    for (int k = 0; k < W; ++k) result[k] = ev[k];
  } else if (rules.evRule == EvRule::kCrease) {
    fas_detail::creaseVertex<W>(result, ev, in + ringIndex(rules.creaseSpokeA, kE) * W,
                                in + ringIndex(rules.creaseSpokeB, kE) * W);
  } else {
    // ((n-2)/n) v + (1/n^2) (sum of edge neighbours + sum of face points)
    const float selfWeight = float(n - 2) / float(n);
    const float ringWeight = 1.0f / float(n * n);
    for (int k = 0; k < W; ++k) {
      float sum = 0.0f;
      for (int i = 0; i < n; ++i) {
        sum += in[ringIndex(i, kE) * W + k] + out[ringIndex(i, kD) * W + k];
      }
      result[k] = selfWeight * ev[k] + ringWeight * sum;
    }
  }
}

// The whole step for one ring block, sequentially (the CPU path; CUDA spreads the loops over a warp).
template <int W>
TESSERA_HD void refineRingStep(const RingRules& rules, const float* in, float* out) {
  const int n = rules.shape.sectors;
  for (int i = 0; i < n; ++i) refineSectorFaces<W>(rules, i, in, out);
  for (int j = 0; j < rules.shape.spokeCount(); ++j) refineSpoke<W>(rules, j, in, out);
  for (int i = 0; i < n; ++i) refineSectorInterior<W>(rules, i, in, out);
  refineExtraordinaryVertex<W>(rules, in, out);
}

}  // namespace tessera
