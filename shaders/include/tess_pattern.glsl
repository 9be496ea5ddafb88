// The tessellation pattern of one patch: which (u,v) each vertex has and which three vertices
// each triangle uses, computable for any vertex or triangle index independently (the mesh path
// needs random access; the compute path uses the same functions so both draw the same mesh).
//
// D3D11-style stitching (MATH.md §5): the interior grid has Nu × Nv steps with
// Nu = max(e0, e2) and Nv = max(e1, e3); each boundary edge k carries exactly e_k + 1 points,
// so the points on an edge depend only on that edge's level. The ring of trapezoids between
// the boundary and the inner grid's outer ring is triangulated by a "zipper" that merges the
// two rails in order of segment midpoints.
//
// Vertex ids: [0, B) boundary points counter-clockwise from (0,0), edge k owning its start
// corner and e_k - 1 inner points (B = Σ e_k); then the (Nu-1)(Nv-1) inner grid points.
// Triangle ids: the four trapezoid strips (edge order), then the inner quads, 2 triangles each.
#ifndef TESSERA_TESS_PATTERN_GLSL
#define TESSERA_TESS_PATTERN_GLSL

#include "tess_pattern_counts.h"

// A vector rather than an array: shader compilers keep vectors in registers even when
// indexed dynamically, where small arrays may go to scratch memory (slow on llvmpipe).
struct TessLevels {
  ivec4 e;  // edges v=0, u=1, v=1, u=0
  int nu;
  int nv;
};

TessLevels makeTessLevels(uvec4 edgeLevels) {
  TessLevels L;
  L.e = max(ivec4(edgeLevels), ivec4(1));
  L.nu = max(L.e[0], L.e[2]);
  L.nv = max(L.e[1], L.e[3]);
  return L;
}

// Sum of the levels of the sides before `side` (0..4).
int boundaryOffset(TessLevels L, int side) {
  ivec4 before = ivec4(lessThan(ivec4(0, 1, 2, 3), ivec4(side)));
  return before.x * L.e.x + before.y * L.e.y + before.z * L.e.z + before.w * L.e.w;
}

int boundaryVertexCount(TessLevels L) { return L.e.x + L.e.y + L.e.z + L.e.w; }

bool isStripLess(TessLevels L) { return L.nu == 1 || L.nv == 1; }

int patternVertexCount(TessLevels L) { return tessPatternVertices(L.e.x, L.e.y, L.e.z, L.e.w); }

int stripTriangleCount(TessLevels L, int side) {
  int n = (side % 2 == 0) ? L.nu : L.nv;
  return L.e[side] + n - 2;
}

int patternTriangleCount(TessLevels L) { return tessPatternTriangles(L.e.x, L.e.y, L.e.z, L.e.w); }

// Where a vertex sits: on boundary side `side` (0..3) at CCW step `step`, or inside (side 4).
struct PatternVertex {
  int side;
  int step;
  vec2 uv;
};

PatternVertex patternVertex(TessLevels L, int id) {
  PatternVertex pv;
  int boundary = boundaryVertexCount(L);
  if (id >= boundary) {
    int k = id - boundary;
    int i = 1 + k % (L.nu - 1);
    int j = 1 + k / (L.nu - 1);
    pv.side = 4;
    pv.step = 0;
    pv.uv = vec2(float(i) / float(L.nu), float(j) / float(L.nv));
    return pv;
  }
  int side = 0;
  int off = 0;
  while (id >= off + L.e[side]) {
    off += L.e[side];
    ++side;
  }
  int i = id - off;
  float e = float(L.e[side]);
  pv.side = side;
  pv.step = i;
  if (side == 0) pv.uv = vec2(float(i) / e, 0.0);
  else if (side == 1) pv.uv = vec2(1.0, float(i) / e);
  else if (side == 2) pv.uv = vec2(float(L.e[2] - i) / e, 1.0);
  else pv.uv = vec2(0.0, float(L.e[3] - i) / e);
  return pv;
}

int boundaryVertexId(TessLevels L, int side, int step) {
  return (boundaryOffset(L, side) + step) % boundaryVertexCount(L);
}

int innerVertexId(TessLevels L, int i, int j) {
  return boundaryVertexCount(L) + (i - 1) + (j - 1) * (L.nu - 1);
}

// Inner-ring point b (0-based, CCW) along the side facing boundary edge `side`.
int innerRailVertexId(TessLevels L, int side, int b) {
  if (side == 0) return innerVertexId(L, b + 1, 1);
  if (side == 1) return innerVertexId(L, L.nu - 1, b + 1);
  if (side == 2) return innerVertexId(L, L.nu - 1 - b, L.nv - 1);
  return innerVertexId(L, 1, L.nv - 1 - b);
}

// A zipper between rails A (na segments) and B (nb segments). Segment a of A has midpoint
// (2a + ca) / da, likewise for B; segments are taken in midpoint order, A first on ties.
struct Zipper {
  int na, ca, da;
  int nb, cb, db;
};

// Merge position of A's segment a: a plus the number of B segments strictly before it.
int zipperPositionOfA(Zipper z, int a) {
  int x = (2 * a + z.ca) * z.db - z.cb * z.da;  // B segment b precedes a iff 2b*da < x
  int before = x <= 0 ? 0 : min(z.nb, (x + 2 * z.da - 1) / (2 * z.da));
  return a + before;
}

// Step k of the merge: (segments of A taken before it, whether step k takes an A segment).
ivec2 zipperStep(Zipper z, int k) {
  int lo = 0;
  int hi = z.na;
  while (lo < hi) {
    int mid = (lo + hi) / 2;
    if (zipperPositionOfA(z, mid) < k) lo = mid + 1;
    else hi = mid;
  }
  bool takesA = lo < z.na && zipperPositionOfA(z, lo) == k;
  return ivec2(lo, takesA ? 1 : 0);
}

// Triangle k of the trapezoid between boundary edge `side` and the inner ring.
ivec3 stripTriangle(TessLevels L, int side, int k) {
  int n = (side % 2 == 0) ? L.nu : L.nv;
  Zipper z = Zipper(L.e[side], 1, 2 * L.e[side], n - 2, 3, 2 * n);
  ivec2 st = zipperStep(z, k);
  int a = st.x;
  int b = k - a;
  int oa = boundaryVertexId(L, side, a);
  if (st.y == 1) return ivec3(oa, boundaryVertexId(L, side, a + 1), innerRailVertexId(L, side, b));
  return ivec3(oa, innerRailVertexId(L, side, b + 1), innerRailVertexId(L, side, b));
}

// Patches one step wide in u (or v): a single zipper between the two long edges, with rail R
// the edge u=1 (or v=0) and rail Q the edge u=0 (or v=1), both running in increasing v (or u).
ivec3 thinPatchTriangle(TessLevels L, int k) {
  bool alongV = L.nu == 1;
  int sideR = alongV ? 1 : 0;
  int sideQ = alongV ? 3 : 2;
  int nr = L.e[sideR];
  int nq = L.e[sideQ];
  Zipper z = Zipper(nr, 1, 2 * nr, nq, 1, 2 * nq);
  ivec2 st = zipperStep(z, k);
  int a = st.x;
  int b = k - a;
  int q0 = boundaryVertexId(L, sideQ, nq - b);
  int r0 = boundaryVertexId(L, sideR, a);
  if (st.y == 1) return ivec3(q0, r0, boundaryVertexId(L, sideR, a + 1));
  return ivec3(q0, r0, boundaryVertexId(L, sideQ, nq - b - 1));
}

// Vertex ids of triangle t, counter-clockwise in (u,v).
ivec3 patternTriangle(TessLevels L, int t) {
  if (isStripLess(L)) return thinPatchTriangle(L, t);
  for (int side = 0; side < 4; ++side) {
    int count = stripTriangleCount(L, side);
    if (t < count) return stripTriangle(L, side, t);
    t -= count;
  }
  int q = t / 2;
  int i = 1 + q % (L.nu - 2);
  int j = 1 + q / (L.nu - 2);
  int v00 = innerVertexId(L, i, j);
  int v10 = innerVertexId(L, i + 1, j);
  int v01 = innerVertexId(L, i, j + 1);
  int v11 = innerVertexId(L, i + 1, j + 1);
  return (t % 2 == 0) ? ivec3(v00, v10, v11) : ivec3(v00, v11, v01);
}

#endif
