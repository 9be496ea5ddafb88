// Triangular base faces as one triangle (docs/ADAPTIVE.md §6a). Catmull-Clark parameterizes a
// triangle as three quad sub-faces, so planned root by root a triangle costs at least three
// one-cell tiles (six triangles) and puts the middles of its edges on its neighbours' sides, where
// OpenSubdiv's uniform rate 1 makes one triangle. When each sub-face became one one-cell tile, the
// face is the triangle through its limit corners, split at the middles of the edges that keep one:
// one triangle with none, two with one, four with all three (two middles: refused). Which edges
// keep their middles is known once stitched (a neighbour that puts one there); a face whose
// triangle without middles is over ε but whose four triangles are within it keeps all three.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/adaptive/adaptive_plan.h"
#include "core/rings/patch_set.h"
#include "core/stitching/line_points.h"
#include "core/stitching/tile_stitching.h"
#include "core/surface/adaptive_surface.h"
#include "core/surface/surface_evaluation.h"

namespace tessera {

// Sub-face k's tile t of a face triangle on its face's edge k: its side 0 stretched over the whole
// edge (`line`, its side 0's place there) from the face's corner k to k + 1, one cell, or two that
// keep their middle.
line_points::LineUse faceEdgeUse(const Tile& tile, uint32_t t, const SideLine& line);

// The point at `along` of that edge, evaluated in the sub-face whose half holds it: the first
// half on sub-face k's side 0, the second on sub-face k + 1's side 3, which runs back from the
// face's corner k + 1.
VertexRequest faceEdgePoint(const Tile& tile, uint32_t t, double along);

// A face triangle's points as stitched (sub-face 0's tile t: sub-faces 1 and 2 at t + 1, t + 2):
// the vertices of the face's corners and of the middles its edges keep; `middles` has bit k for
// edge k (from corner k to k + 1) keeping its middle, -1 when an edge has another point besides
// its corners and middle.
struct FaceTrianglePoints {
  uint32_t corner[3], middle[3];
  int middles;
};
FaceTrianglePoints faceTrianglePoints(const Stitching& stitching, size_t t);

class FaceTriangles {
 public:
  explicit FaceTriangles(size_t faces) : refused_(faces, 0), mode_(faces, kNone), bounds_(faces) {}

  // Marks (Tile::faceTriangle) the tiles of every triangular face not refused whose sub-faces are
  // each one one-cell tile, whose triangle without middles, or else with all three, is within
  // their ε, and whose neighbours' tiles, as planned, put no point on its edges but their middles
  // and only middles it has a triangulation for within ε; their bound becomes that
  // triangulation's.
  void join(AdaptivePlan& plan, const PatchSet& patches, const AdaptiveSurface& surface);

  // Gives each face triangle the bound of the middles its edges kept once stitched; refuses (their
  // sub-faces' tiles serve them next time) those whose middles have no triangulation within ε, and
  // returns whether none was.
  bool hold(AdaptivePlan& plan, const Stitching& stitching, const SurfaceTree& tree);

 private:
  enum Mode : uint8_t { kNone, kOneCell, kKeepsMiddles };  // edges of one cell, or two keeping the middle
  // A face's bounds by the middles kept (none, all three, or only edge j's) and its ε.
  struct Bounds {
    float none = INFINITY, all = INFINITY, one[3] = {INFINITY, INFINITY, INFINITY}, tolerance = 0;
    float forMiddles(int middles) const;
  };
  void candidate(SurfaceEvaluator& evaluator, const AdaptivePlan& plan, const AdaptiveSurface& surface, int f);
  int neighbourMiddles(const AdaptivePlan& plan, const AdaptiveSurface& surface, int f) const;

  std::vector<uint8_t> refused_;
  std::vector<Mode> mode_;
  std::vector<Bounds> bounds_;
};

}  // namespace tessera
