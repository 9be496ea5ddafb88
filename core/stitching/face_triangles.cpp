#include "core/stitching/face_triangles.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>

#include "core/surface/surface_evaluation.h"

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

Vec3d closestOnSegment(const Vec3d& p, const Vec3d& a, const Vec3d& b) {
  const Vec3d d = b - a;
  const double dd = dot(d, d);
  return dd > 0 ? a + d * std::clamp(dot(p - a, d) / dd, 0.0, 1.0) : a;
}

}  // namespace

line_points::LineUse faceEdgeUse(const Tile& tile, uint32_t t, const SideLine& line) {
  line_points::LineUse use;
  use.cells = tile.faceMiddles ? 2 : 1;
  use.kept = use.cells;
  use.a = line.origin * use.cells, use.sign = line.sign, use.exp = 0;
  use.tile = t, use.side = 0;
  use.t0 = 0, use.t1 = kLineScale;
  return use;
}

VertexRequest faceEdgePoint(const Tile& tile, uint32_t t, double along) {
  if (along <= 0.5) return {t, 2 * along, 0, 0};
  return {t - (tile.faceTriangle - 1u) + tile.faceTriangle % 3u, 0, 2 * (1 - along), 0};
}

FaceTrianglePoints faceTrianglePoints(const Stitching& stitching, size_t t) {
  FaceTrianglePoints face{{}, {UINT32_MAX, UINT32_MAX, UINT32_MAX}, 0};
  for (int k = 0; k < 3; ++k) {
    size_t count;
    const SidePoint* points = stitching.side(t + size_t(k), 0, count);
    face.corner[k] = points[0].vertex;
    if (count == 3 && points[1].at == 0.5) {
      face.middle[k] = points[1].vertex;
      face.middles |= 1 << k;
    } else if (count != 2) {
      face.middles = -1;
    }
  }
  return face;
}

float FaceTriangles::Bounds::forMiddles(int middles) const {
  if (middles == 0) return none;
  if (middles == 7) return all;
  if (middles > 0 && std::has_single_bit(unsigned(middles))) return one[std::countr_zero(unsigned(middles))];
  return INFINITY;  // two middles, or other points: no triangulation
}

// docs/ADAPTIVE.md §6a: each sub-face's cell is within its tile's bound b_k of its two triangles
// through its corners (V_k, M_k, C, M_{k-1}), for the diagonal that bound assumes. A map that
// sends those corners to points of the face's triangulation and is linear on each of the cell's
// triangles moves every point by at most the largest of its corners' moves; when the mapped
// triangles tile the triangulation, it is within max_k (b_k + that move) of the surface. Kept
// middles stay; the others go to their edge's chord middle, and C to the centroid G (no middle),
// the middles' centroid (all three, diagonal M_k–M_{k−1}) or the point of the fold M_j–V_{j+2}
// nearest it (only M_j, sub-face j + 2 on diagonal V_{j+2}–C).
void FaceTriangles::candidate(SurfaceEvaluator& evaluator, const AdaptivePlan& plan, const AdaptiveSurface& surface, int f) {
  mode_[f] = kNone;
  if (refused_[f]) return;
  const uint32_t first = joinableFace(plan, surface, f);
  if (first == UINT32_MAX) return;
  const Tile* tiles[3];
  Vec3d corner[3], middle[3];
  Bounds& bounds = bounds_[f];
  bounds.tolerance = INFINITY;
  for (uint32_t k = 0; k < 3; ++k) {
    tiles[k] = &plan.tiles[plan.rootFirstTile[first + k]];
    bounds.tolerance = std::min(bounds.tolerance, tiles[k]->tolerance);
    const NodeSquare top{surface.tree.roots[first + k].node, 0, 0, 0};
    corner[k] = evaluator.evaluate(top, 0, 0).position;
    middle[k] = evaluator.evaluate(top, 1, 0).position;
  }
  const Vec3d centre = evaluator.evaluate({surface.tree.roots[first].node, 0, 0, 0}, 1, 1).position;
  double bow[3];  // |M_k − chord middle of edge k|
  for (int k = 0; k < 3; ++k) bow[k] = length(middle[k] - (corner[k] + corner[(k + 1) % 3]) * 0.5);
  auto b = [&](int k) { return double(tiles[k % 3]->bound); };
  // Which diagonal a sub-face's bound assumes (Tile::diagonal): 0 any, 1 + d diagonal d.
  auto allows = [&](int k, int d) { return tiles[k % 3]->diagonal == 0 || tiles[k % 3]->diagonal == 1 + d; };
  constexpr double kInf = INFINITY, kRound = 1 + 1e-9;
  const double toCentroid = length(centre - (corner[0] + corner[1] + corner[2]) * (1.0 / 3));
  const double toMiddles = length(centre - (middle[0] + middle[1] + middle[2]) * (1.0 / 3));
  double none = 0, all = 0;
  for (int k = 0; k < 3; ++k) {
    none = std::max(none, b(k) + std::max({toCentroid, bow[k], bow[(k + 2) % 3]}));
    all = std::max(all, allows(k, 1) ? b(k) + toMiddles : kInf);
  }
  bounds.none = float(none * kRound), bounds.all = float(all * kRound);
  for (int j = 0; j < 3; ++j) {
    const double c = length(centre - closestOnSegment(centre, middle[j], corner[(j + 2) % 3]));
    const double one = std::max({b(j) + std::max(c, bow[(j + 2) % 3]), b(j + 1) + std::max(c, bow[(j + 1) % 3]),
                                 allows(j + 2, 0) ? b(j + 2) + std::max({c, bow[(j + 2) % 3], bow[(j + 1) % 3]}) : kInf});
    bounds.one[j] = float(one * kRound);
  }
  if (bounds.none <= bounds.tolerance) {
    mode_[f] = kOneCell;
  } else if (bounds.all <= bounds.tolerance) {
    mode_[f] = kKeepsMiddles;
  }
}

// The middles (bit k: edge k) the tiles beside face f put on its edges as planned, face triangles
// beside it as they stand; -1 if one puts another point there. On a line the points are every
// side's corners, then a side's own points wherever a gap is wider than its cell (§7), so with the
// face's corners there a side adds none but the middle only if it spans the whole edge in at most
// two cells or half of it in one.
int FaceTriangles::neighbourMiddles(const AdaptivePlan& plan, const AdaptiveSurface& surface, int f) const {
  const SeamLines& lines = surface.lines;
  const uint32_t first = uint32_t(surface.tree.faceFirstRoot[f]);
  int middles = 0;
  for (int k = 0; k < 3; ++k) {
    const SeamLines::Line& line = lines.lines[lines.lineOf[4 * size_t(first + k)]];
    for (uint32_t i = line.firstSide; i < line.firstSide + line.sideCount; ++i) {
      const uint32_t side = lines.rootSides[i], r = side / 4;
      const int rootSide = int(side % 4);
      if (r >= first && r < first + 3) continue;
      const SurfaceRoot& root = surface.tree.roots[r];
      if (root.subFace >= 0 && mode_[root.baseFace] != kNone) {
        if (mode_[root.baseFace] == kKeepsMiddles) middles |= 1 << k;
        continue;
      }
      const double halves = lines.sideLine[side].halves;
      for (uint32_t t = plan.rootFirstTile[r]; t < plan.rootFirstTile[r + 1]; ++t) {
        const Tile& tile = plan.tiles[t];
        if (!tile.onRootSide(rootSide)) continue;
        const int cells = rootSide == 0 || rootSide == 2 ? tile.ru : tile.rv;
        const double span = (rootSide == 0 || rootSide == 2 ? tile.width() : tile.height()) / halves;  // exact
        if (span == 1 && cells <= 2) {
          middles |= (cells == 2) << k;
        } else if (span == 0.5 && cells == 1) {
          middles |= 1 << k;
        } else {
          return -1;
        }
      }
    }
  }
  return middles;
}

void FaceTriangles::join(AdaptivePlan& plan, const PatchSet& patches, const AdaptiveSurface& surface) {
  const int faces = int(surface.tree.faceFirstRoot.size());
  tbb::enumerable_thread_specific<SurfaceEvaluator> evaluators([&] { return SurfaceEvaluator(surface.tree, patches); });
  tbb::parallel_for(tbb::blocked_range<int>(0, faces, 512), [&](const auto& range) {
    for (int f = range.begin(); f != range.end(); ++f) {
      if (surface.seams.faceSizes[f] == 3) candidate(evaluators.local(), plan, surface, f);
    }
  });
  std::vector<int> candidates;
  for (int f = 0; f < faces; ++f) {
    if (mode_[f] != kNone) candidates.push_back(f);
  }
  // A face let go gives its neighbours middles: until none is.
  for (bool dropped = true; dropped;) {
    dropped = false;
    for (int f : candidates) {
      if (mode_[f] == kNone) continue;
      const int middles = neighbourMiddles(plan, surface, f);
      const bool fits = middles >= 0 && (mode_[f] == kKeepsMiddles || bounds_[f].forMiddles(middles) <= bounds_[f].tolerance);
      if (!fits) mode_[f] = kNone, dropped = true;
    }
  }
  for (int f : candidates) {
    if (mode_[f] == kNone) continue;
    // The bound needs no side points but its corners and middles, which hold() checks in place
    // of the sub-faces' pending pairs.
    const uint32_t first = uint32_t(surface.tree.faceFirstRoot[f]);
    for (uint32_t k = 0; k < 3; ++k) {
      Tile& tile = plan.tiles[plan.rootFirstTile[first + k]];
      tile.bound = mode_[f] == kKeepsMiddles ? bounds_[f].all : bounds_[f].none;
      tile.tolerance = bounds_[f].tolerance;
      tile.pendingPair = false;
      tile.faceTriangle = uint8_t(k + 1);
      tile.faceMiddles = mode_[f] == kKeepsMiddles;
    }
  }
}

bool FaceTriangles::hold(AdaptivePlan& plan, const Stitching& stitching, const SurfaceTree& tree) {
  bool held = true;
  for (size_t r = 0; r + 1 < plan.rootFirstTile.size(); ++r) {
    const size_t t = plan.rootFirstTile[r];
    if (t == plan.rootFirstTile[r + 1] || plan.tiles[t].faceTriangle != 1) continue;
    const int face = tree.roots[r].baseFace;
    const float bound = bounds_[face].forMiddles(faceTrianglePoints(stitching, t).middles);
    if (bound <= plan.tiles[t].tolerance) {
      for (size_t k = 0; k < 3; ++k) plan.tiles[t + k].bound = bound;
      continue;
    }
    refused_[face] = 1;
    held = false;
  }
  return held;
}

}  // namespace tessera
