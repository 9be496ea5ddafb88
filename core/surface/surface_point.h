// One point of the limit surface from the surface tree's arrays: the descent from a node known to
// hold the point to the leaf that does, and that leaf's piece evaluated there with its unit
// normal. Host-device: the CPU's SurfaceEvaluator (core/surface/surface_evaluation.h) and the CUDA
// engine's vertex kernel (gpu/cuda/vertex_threads.h) run this same code, so both give a vertex
// the same bits (MATH.md §5: no contraction on either side).
#pragma once

#include <cstdint>
#include <cstring>

#include "core/base/host_device.h"
#include "core/math/bezier_net.h"
#include "core/math/bicubic.h"
#include "core/math/dyadic.h"
#include "core/surface/surface_tree.h"

namespace tessera {

// A node's square in its root: [ix, ix + 1] × [iy, iy + 1] scaled by 2^-level.
struct NodeSquare {
  uint32_t node = kNoNode;
  int level = 0;
  uint64_t ix = 0, iy = 0;

  // Quadrant q (SurfaceNode's child order) of a node whose first child is `firstChild`.
  TESSERA_HD NodeSquare childAt(uint32_t firstChild, int q) const {
    return {firstChild + uint32_t(q), level + 1, 2 * ix + uint64_t(q & 1), 2 * iy + uint64_t(q >> 1)};
  }
  NodeSquare child(const SurfaceTree& tree, int q) const { return childAt(tree.nodes[node].firstChild, q); }
  double size() const { return exp2i(-level); }
};

struct SurfaceSample {
  Vec3d position;
  Vec3d normal;  // unit; oriented like the mesh (counter-clockwise faces seen from it)
};

// 2^e (as exp2i, without its constexpr bit_cast, which device code lacks).
TESSERA_HD double powerOfTwo(int e) {
  const uint64_t bits = uint64_t(1023 + e) << 52;
  double value;
  memcpy(&value, &bits, sizeof value);
  return value;
}

// A point (u, v) of the root inside `at`'s square: the leaf below `at` that holds it and where it
// lies in that leaf's square, clamped to [0, 1]² (a point on a quadrant boundary goes to the
// upper quadrant).
struct LeafPoint {
  NodeSquare leaf;
  double x, y;
};
TESSERA_HD LeafPoint descendToLeaf(const SurfaceNode* nodes, NodeSquare at, double u, double v) {
  for (;;) {
    const double scale = powerOfTwo(at.level);
    const double x = u * scale - double(at.ix), y = v * scale - double(at.iy);
    const uint32_t firstChild = nodes[at.node].firstChild;
    if (firstChild == kNoNode) return {at, x < 0 ? 0.0 : x > 1 ? 1.0 : x, y < 0 ? 0.0 : y > 1 ? 1.0 : y};
    at = at.childAt(firstChild, (y >= 0.5 ? 2 : 0) + (x >= 0.5 ? 1 : 0));
  }
}

// A leaf's piece as evaluation reads it: 16 control points relative to `offset` (a ring's centre
// for ring pieces, so that deep levels keep their precision), either a B-spline net in the piece's
// own (s, t) frame, placed in the root by `orientation` (Orientation::code()), or a Bézier net in
// root orientation (an EV bottom's stand-in).
struct PieceNet {
  const Vec3* points;
  bool bezier;
  uint8_t orientation;
  Vec3d offset;
};

// Piece parameters of a point at (x, y) ∈ [0,1]² of the piece's square in root orientation.
TESSERA_HD void pieceParameters(const Orientation& o, double x, double y, double& s, double& t) {
  s = o.su * x + o.sv * y + (o.su + o.sv < 0 ? 1 : 0);
  t = o.tu * x + o.tv * y + (o.tu + o.tv < 0 ? 1 : 0);
}

template <typename Acc>
TESSERA_HD PatchSample evaluatePiece(const PieceNet& piece, double x, double y) {
  if (piece.bezier) return evaluateBezier<Vec3, Acc>(piece.points, x, y);
  double s, t;
  pieceParameters(Orientation::fromCode(piece.orientation), x, y, s, t);
  return evaluateBspline<Vec3, Acc>(piece.points, s, t);
}

// A unit vector across direction d (any, when d vanishes): the cross product with the axis d
// leans on least.
TESSERA_HD Vec3d anyNormalAcross(const Vec3d& d) {
  const double ax = d.x < 0 ? -d.x : d.x, ay = d.y < 0 ? -d.y : d.y, az = d.z < 0 ? -d.z : d.z;
  const Vec3d axis = ax <= ay && ax <= az ? Vec3d(1, 0, 0) : ay <= az ? Vec3d(0, 1, 0) : Vec3d(0, 0, 1);
  const Vec3d n = cross(d, axis);
  const double l = length(n);
  return l > 0 ? n * (1.0 / l) : Vec3d(0, 0, 1);
}

// The piece's point at (x, y) of its square, with its unit normal. `Acc` is evaluateTensorPatch's
// accumulator (Vec3d, or the host's SIMD lanes: the same bits).
template <typename Acc>
TESSERA_HD SurfaceSample samplePiece(const PieceNet& piece, double x, double y) {
  PatchSample p = evaluatePiece<Acc>(piece, x, y);
  SurfaceSample sample{p.position + piece.offset, Vec3d()};
  // A degenerate point (the derivatives vanish, as at a ring's corner, or are parallel, as on the
  // fold where a two-sided face meets a sharp corner) takes the normal of a point a step inside,
  // the steps growing toward the piece's centre; a piece degenerate throughout gets any unit
  // normal across its one direction.
  const double steps[4] = {1e-6, 1e-3, 0.125, 0.5};
  for (int nudges = 0;; ++nudges) {
    // The normal's length found once: it is both the unit scale and the degeneracy test.
    const Vec3d n = cross(p.dPds, p.dPdt);
    const double l = length(n);
    if (l > 0) {
      sample.normal = n * (1.0 / l) * double(Orientation::fromCode(piece.orientation).handedness());
      return sample;
    }
    if (nudges == 4) {
      sample.normal = anyNormalAcross(p.dPds + p.dPdt);
      return sample;
    }
    x += x < 0.5 ? steps[nudges] : -steps[nudges];
    y += y < 0.5 ? steps[nudges] : -steps[nudges];
    p = evaluatePiece<Acc>(piece, x, y);
  }
}

}  // namespace tessera
