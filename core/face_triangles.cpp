#include "core/face_triangles.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "core/surface_evaluation.h"

namespace tessera {

namespace {

// The first root of triangular face f when its three sub-faces can make one triangle: each is one
// one-cell tile, no corner splits its normal, no edge is infinitely sharp, and sub-face k's side 0
// and sub-face k + 1's side 3 are the two halves of edge k, meeting at its middle (the layout
// docs/ADAPTIVE.md §6a relies on). UINT32_MAX otherwise.
uint32_t joinableFace(const AdaptivePlan& plan, const AdaptiveSurface& surface, int f) {
  if (surface.seams.faceSizes[f] != 3) return UINT32_MAX;
  const uint32_t first = uint32_t(surface.tree.faceFirstRoot[f]);
  const SeamLines& lines = surface.lines;
  for (uint32_t k = 0; k < 3; ++k) {
    const uint32_t r = first + k, next = first + (k + 1) % 3;
    const SurfaceRoot& root = surface.tree.roots[r];
    if (root.node == kNoNode || root.subFace != int(k)) return UINT32_MAX;
    if (plan.rootFirstTile[r + 1] - plan.rootFirstTile[r] != 1) return UINT32_MAX;
    const Tile& tile = plan.tiles[plan.rootFirstTile[r]];
    if (tile.level != 0 || tile.ru != 1 || tile.rv != 1 || tile.cellwise) return UINT32_MAX;
    for (int c = 0; c < 4; ++c) {
      if (lines.cornerQualifier[4 * size_t(r) + c] >= 0) return UINT32_MAX;
    }
    const SideLine& half = lines.sideLine[4 * size_t(r)];
    const SideLine& other = lines.sideLine[4 * size_t(next) + 3];
    if (lines.lineOf[4 * size_t(r)] != lines.lineOf[4 * size_t(next) + 3] || half.sharp || half.halves != 2 ||
        other.origin != half.origin + half.sign || other.sign != -half.sign) {
      return UINT32_MAX;
    }
  }
  return first;
}

// docs/ADAPTIVE.md §6a: each sub-face's cell is within its tile's bound b_k of the two triangles
// through its corners (V_k, M_k, C, M_{k-1}); mapping those corners linearly to V_k, the middle
// of edge k, the centroid G and the middle of edge k − 1 of the triangle V_0 V_1 V_2 moves every
// point of the cell's triangles by at most the largest of its corners' moves (the move is linear
// on each triangle), and the mapped triangles tile V_0 V_1 V_2. So the triangle is within
// max_k (b_k + that move) of the surface over the face.
double triangleBound(SurfaceEvaluator& evaluator, const SurfaceTree& tree, const AdaptivePlan& plan, uint32_t first) {
  Vec3d corner[3], middle[3];
  for (uint32_t k = 0; k < 3; ++k) {
    const NodeSquare top{tree.roots[first + k].node, 0, 0, 0};
    corner[k] = evaluator.evaluate(top, 0, 0).position;
    middle[k] = evaluator.evaluate(top, 1, 0).position;
  }
  const Vec3d centre = evaluator.evaluate({tree.roots[first].node, 0, 0, 0}, 1, 1).position;
  const double centreMove = length(centre - (corner[0] + corner[1] + corner[2]) * (1.0 / 3));
  double middleMove[3];
  for (int k = 0; k < 3; ++k) middleMove[k] = length(middle[k] - (corner[k] + corner[(k + 1) % 3]) * 0.5);
  double bound = 0;
  for (int k = 0; k < 3; ++k) {
    const double move = std::max({centreMove, middleMove[k], middleMove[(k + 2) % 3]});
    bound = std::max(bound, double(plan.tiles[plan.rootFirstTile[first + k]].bound) + move);
  }
  return bound * (1 + 1e-9);
}

}  // namespace

void joinFaceTriangles(AdaptivePlan& plan, const PatchSet& patches, const AdaptiveSurface& surface,
                       const std::vector<uint8_t>& refused) {
  const int faces = int(surface.tree.faceFirstRoot.size());
  tbb::enumerable_thread_specific<SurfaceEvaluator> evaluators([&] { return SurfaceEvaluator(surface.tree, patches); });
  tbb::parallel_for(tbb::blocked_range<int>(0, faces, 512), [&](const auto& range) {
    for (int f = range.begin(); f != range.end(); ++f) {
      if (refused[f]) continue;
      const uint32_t first = joinableFace(plan, surface, f);
      if (first == UINT32_MAX) continue;
      Tile* tiles[3];
      float tolerance = INFINITY;
      for (uint32_t k = 0; k < 3; ++k) {
        tiles[k] = &plan.tiles[plan.rootFirstTile[first + k]];
        tolerance = std::min(tolerance, tiles[k]->tolerance);
      }
      const double bound = triangleBound(evaluators.local(), surface.tree, plan, first);
      if (!(bound <= tolerance)) continue;
      // The triangle's bound needs no side points but its corners, which faceTrianglesHold checks
      // in place of the sub-faces' pending pairs.
      for (int k = 0; k < 3; ++k) {
        tiles[k]->bound = float(bound), tiles[k]->tolerance = tolerance;
        tiles[k]->pendingPair = false;
        tiles[k]->faceTriangle = uint8_t(k + 1);
      }
    }
  });
}

bool faceTrianglesHold(const AdaptivePlan& plan, const Stitching& stitching, const SurfaceTree& tree,
                       std::vector<uint8_t>& refused) {
  bool held = true;
  for (size_t t = 0; t < plan.tiles.size(); ++t) {
    if (plan.tiles[t].faceTriangle == 0) continue;
    size_t count;
    stitching.side(t, 0, count);
    if (count == 2) continue;
    // Tile t is sub-face k of its face: the face of its root.
    const size_t root = size_t(std::upper_bound(plan.rootFirstTile.begin(), plan.rootFirstTile.end(), uint32_t(t)) -
                               plan.rootFirstTile.begin()) - 1;
    refused[tree.roots[root].baseFace] = 1;
    held = false;
  }
  return held;
}

}  // namespace tessera
