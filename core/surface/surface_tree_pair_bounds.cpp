// The pair bounds and side bows of the surface tree's nodes (docs/ADAPTIVE.md §3, §3a, §3b),
// gathered leaf by leaf down each root: at equal parameters, through each node's per-axis maps and
// through its diagonal map.
#include <algorithm>
#include <bit>
#include <optional>

#include "core/bounds/diagonal_pair_bound.h"
#include "core/bounds/flat_pair_bound.h"
#include "core/math/bicubic.h"
#include "core/math/dyadic.h"
#include "core/surface/surface_evaluation.h"
#include "core/surface/surface_tree_builder.h"

namespace tessera::surface_tree_building {

// A leaf's deviation from each ancestor's bilinear interpolant B (restricted to the leaf, B is the
// bilinear of its values at the leaf's corners), and along the ancestor's sides the leaf touches,
// from the ancestor's chords; and the same through the ancestor's axis maps (§3a: B at the
// preimages of the leaf's corners, the leaf's own net unchanged). First a cheap bound: the
// leaf's deviation from its own bilinear plus the largest gap between the two bilinears, at a
// leaf corner (their difference is bilinear); the de Casteljau bound only where the cheap one
// could raise the maximum.
void TreeBuilder::leafAgainstAncestors(uint32_t index, const BezierNet& net, double r, int level, uint64_t ix,
                                       uint64_t iy, const std::vector<Ancestor>& path) {
  Vec3d own[4];
  for (int k = 0; k < 4; ++k) own[k] = net[kCornerIndex[k]];
  const double ownPair = r + splitNetDistance(net, bilinearNet(own));
  double ownBow[4];
  const std::array<double, 4> chord = chordBows(net, own);
  for (int side = 0; side < 4; ++side) ownBow[side] = r + chord[side];
  // The leaf's own bounds, for the ancestor it stands for in the diagonal bound.
  pair_[index] = ownPair;
  std::copy(ownBow, ownBow + 4, bow_[index].begin());
  for (const Ancestor& a : path) {
    const std::array<Vec3d, 4>& c = corners_[a.node];
    double x0, y0, scale;
    a.square(level, ix, iy, x0, y0, scale);
    const bool touches[4] = {y0 == 0, x0 + scale == 1, y0 + scale == 1, x0 == 0};
    // The leaf against B at the same parameters, or against B at the preimage of its corners.
    auto against = [&](double u0, double u1, double v0, double v1, double& pair, std::array<double, 4>& bows) {
      Vec3d leafCorners[4];
      double gap[4];
      const double cx[4] = {u0, u1, u1, u0}, cy[4] = {v0, v0, v1, v1};
      for (int k = 0; k < 4; ++k) {
        leafCorners[k] = bilinearAt(c.data(), cx[k], cy[k]);
        gap[k] = length(own[k] - leafCorners[k]);
      }
      const double cheap = ownPair + *std::max_element(gap, gap + 4);
      if (cheap > pair) pair = std::max(pair, std::min(cheap, r + splitNetDistance(net, bilinearNet(leafCorners))));
      for (int side = 0; side < 4; ++side) {
        if (!touches[side]) continue;
        int from, to;
        sideCorners(side, from, to);
        const double cheapBow = ownBow[side] + std::max(gap[from], gap[to]);
        if (cheapBow <= bows[side]) continue;
        const double bow = r + sideChordDistance(net, side, leafCorners[from], leafCorners[to]);
        bows[side] = std::max(bows[side], std::min(cheapBow, bow));
      }
    };
    against(x0, x0 + scale, y0, y0 + scale, pair_[a.node], bow_[a.node]);
    if (!a.u.isIdentity() || !a.v.isIdentity()) {
      against(a.u.preimage(x0), a.u.preimage(x0 + scale), a.v.preimage(y0), a.v.preimage(y0 + scale),
              pairReparam_[a.node], bowReparam_[a.node]);
    }
    if (!a.diagonal || level - a.level > kDiagonalReach) continue;
    const LeafOwn leaf{{own[0], own[1], own[2], own[3]}, x0, y0, scale, ownPair, {ownBow[0], ownBow[1], ownBow[2], ownBow[3]}};
    const LazyNet whole{nullptr, 0, true, net};
    pieceAgainstDiagonal(&whole, r, leaf, x0, y0, scale, *a.diagonal, pairDiagonal_[a.node], bowDiagonal_[a.node]);
  }
}

// The samples that pick a node's axis maps: its pieces' spans and, at their corners, where the
// surface projects onto the node's bilinear B across each axis. log2(kCells) levels down, every
// corner of a subtree that can sit on a breakpoint (a multiple of 1/kCells) is the subtree's
// own, so the walk stops there.
void TreeBuilder::gatherAxisSamples(uint32_t index, int depth, uint64_t ix, uint64_t iy, const std::array<Vec3d, 4>& c,
                                    AxisMapBuilder& u, AxisMapBuilder& v) const {
  const SurfaceNode& node = tree_.nodes[index];
  constexpr int kSampleDepth = std::countr_zero(unsigned(AxisMap::kCells));
  if (!node.isLeaf() && depth < kSampleDepth) {
    for (int q = 0; q < 4; ++q) {
      gatherAxisSamples(node.firstChild + q, depth + 1, 2 * ix + uint64_t(q & 1), 2 * iy + uint64_t(q >> 1), c, u, v);
    }
    return;
  }
  const double size = exp2i(-depth), x0 = double(ix) * size, y0 = double(iy) * size;
  u.addPiece(x0, x0 + size);
  v.addPiece(y0, y0 + size);
  const double cx[4] = {x0, x0 + size, x0 + size, x0}, cy[4] = {y0, y0, y0 + size, y0 + size};
  for (int k = 0; k < 4; ++k) {
    const Vec3d& f = corners_[index][k];
    // B's lines through the corner: across u (from u = 0 to 1) and across v.
    const Vec3d a = bilinearAt(c.data(), 0, cy[k]), b = bilinearAt(c.data(), 1, cy[k]);
    const Vec3d p = bilinearAt(c.data(), cx[k], 0), q = bilinearAt(c.data(), cx[k], 1);
    const double across = dot(b - a, b - a), along = dot(q - p, q - p);
    if (across > 0) u.addSample(cx[k], dot(f - a, b - a) / across);
    if (along > 0) v.addSample(cy[k], dot(f - p, q - p) / along);
  }
}

// The surface at the grid points (i, j) / kCells of a node (index i + kPoints j) for its diagonal
// maps: corners of its descendants kCells levels down, or points of a leaf above that.
void TreeBuilder::gatherGridSamples(uint32_t index, int depth, uint64_t ix, uint64_t iy, Vec3d* grid) const {
  constexpr int kGridDepth = std::countr_zero(unsigned(DiagonalMap::kCells));
  const SurfaceNode& node = tree_.nodes[index];
  if (depth < kGridDepth && !node.isLeaf()) {
    for (int q = 0; q < 4; ++q) {
      gatherGridSamples(node.firstChild + q, depth + 1, 2 * ix + uint64_t(q & 1), 2 * iy + uint64_t(q >> 1), grid);
    }
    return;
  }
  const int span = DiagonalMap::kCells >> depth;  // grid cells along the node's side
  const int i0 = int(ix) * span, j0 = int(iy) * span;
  if (depth == kGridDepth) {
    for (int c = 0; c < 4; ++c) grid[i0 + (c == 1 || c == 2) + DiagonalMap::kPoints * (j0 + (c >= 2))] = corners_[index][c];
    return;
  }
  double r;
  const BezierNet net = netOrStandIn(node, r);
  for (int b = 0; b <= span; ++b) {
    for (int a = 0; a <= span; ++a) {
      grid[i0 + a + DiagonalMap::kPoints * (j0 + b)] = evaluateBezier(net.data(), double(a) / span, double(b) / span).position;
    }
  }
}

// The diagonal whose pair, through its map, lies nearer the surface at the grid points.
DiagonalMap TreeBuilder::diagonalMap(uint32_t index) const {
  Vec3d grid[DiagonalMap::kPoints * DiagonalMap::kPoints];
  gatherGridSamples(index, 0, 0, 0, grid);
  const Vec3d* c = corners_[index].data();
  const DiagonalMap first(0, c, grid), second(1, c, grid);
  return second.gridGap() < first.gridGap() ? second : first;
}

void TreeBuilder::directPairBounds(uint32_t index, int level, uint64_t ix, uint64_t iy, std::vector<Ancestor>& path) {
  const SurfaceNode& node = tree_.nodes[index];
  if (node.isLeaf()) {
    double r;
    const BezierNet net = netOrStandIn(node, r);
    leafAgainstAncestors(index, net, r, level, ix, iy, path);
    standForLeaves(index, level, ix, iy, path);
    return;
  }
  {
    AxisMapBuilder u, v;
    gatherAxisSamples(index, 0, 0, 0, corners_[index], u, v);
    std::optional<DiagonalMap> diagonal;
    if (node.pairBound > kDiagonalFloor * floor_) {
      diagonal = diagonalMap(index);
      // Its value at the grid points starts the maximum: the cheap bounds then skip more pieces.
      pairDiagonal_[index] = diagonal->gridGap();
    }
    path.push_back({index, level, ix, iy, u.build(), v.build(), diagonal});
  }
  const bool reparam = !path.back().u.isIdentity() || !path.back().v.isIdentity();
  // 1 + the diagonal of this node's map; 0: it has none.
  const uint8_t diagonal = path.back().diagonal ? uint8_t(1 + path.back().diagonal->diagonal()) : 0;
  for (int q = 0; q < 4; ++q) {
    directPairBounds(node.firstChild + q, level + 1, 2 * ix + uint64_t(q & 1), 2 * iy + uint64_t(q >> 1), path);
  }
  path.pop_back();
  // At equal parameters or through the axis maps (§3a, whichever direct bound is smaller, each
  // with the twist), against the stand-in's (§4); then through the diagonal map (§3b, no twist,
  // that diagonal only) if its pair bound is smaller still, with its own bows.
  SurfaceNode& self = tree_.nodes[index];
  const std::array<Vec3d, 4>& c = corners_[index];
  const double twist = length(c[0] - c[1] + c[2] - c[3]) / 4;
  double pair = pair_[index];
  std::array<double, 4> bows = bow_[index];
  if (reparam && pairReparam_[index] < pair) pair = pairReparam_[index], bows = bowReparam_[index];
  pair = std::min(double(self.pairBound), (pair + twist) * (1 + 1e-9));
  for (int side = 0; side < 4; ++side) bows[side] = std::min(double(self.sideBow[side]), bows[side] * (1 + 1e-9));
  uint8_t kept = 0;
  if (diagonal != 0 && pairDiagonal_[index] < pair) {
    pair = pairDiagonal_[index] * (1 + 1e-9), kept = diagonal;
    for (int side = 0; side < 4; ++side) bows[side] = bowDiagonal_[index][side] * (1 + 1e-9);
  }
  self.pairBound = roundUp(pair);
  for (int side = 0; side < 4; ++side) self.sideBow[side] = roundUp(bows[side]);
  self.pairDiagonal = kept;
  flattenNodePair(index);
  standForLeaves(index, level, ix, iy, path);
}

// §3d over a node of several pieces: its descendants kFlatReach levels down stand in with their
// corners grown by their (final) pair bounds, and along the node's sides with their corners grown
// by their bows; leaves above that with their nets (EV bottoms' stand-ins grown by r).
void TreeBuilder::gatherFlat(uint32_t index, int depth, uint64_t ix, uint64_t iy, FlatGather& gather) const {
  const SurfaceNode& node = tree_.nodes[index];
  const uint8_t on = sidesTouched(ix, iy, depth);
  if (!node.isLeaf() && depth < kFlatReach) {
    for (int q = 0; q < 4; ++q) {
      gatherFlat(node.firstChild + q, depth + 1, 2 * ix + uint64_t(q & 1), 2 * iy + uint64_t(q >> 1), gather);
    }
    return;
  }
  if (!node.isLeaf()) {
    const std::array<Vec3d, 4>& c = corners_[index];
    for (int k = 0; k < 4; ++k) {
      gather.addPoint(c[k], node.pairBound);
      if (!(on >> k & 1)) continue;
      gather.addSidePoint(k, c[k], node.sideBow[k]);
      gather.addSidePoint(k, c[(k + 1) % 4], node.sideBow[k]);
    }
    return;
  }
  double r;
  const BezierNet net = netOrStandIn(node, r);
  gather.addNet(net, r, on);
}

void TreeBuilder::flattenNodePair(uint32_t index) {
  SurfaceNode& node = tree_.nodes[index];
  if (!(node.pairBound > kDiagonalFloor * floor_)) return;
  const Vec3d* corners = corners_[index].data();
  FlatGather gather(corners);
  if (!gather.valid()) return;
  gatherFlat(index, 0, 0, 0, gather);
  keepFlatPair(node, gather.bound(), corners);
}

// A node kDiagonalReach + 1 levels below an ancestor stands there for all its leaves in the
// diagonal bound (§3b): its distance from its bilinear and its bows (the direct bounds at equal
// parameters) plus the bilinear gaps at its corners, so a leaf costs the diagonal bound at most
// kDiagonalReach ancestors, however deep the tree.
void TreeBuilder::standForLeaves(uint32_t index, int level, uint64_t ix, uint64_t iy, const std::vector<Ancestor>& path) {
  if (path.size() <= size_t(kDiagonalReach)) return;
  const Ancestor& a = path[path.size() - 1 - kDiagonalReach];
  if (!a.diagonal) return;
  double x0, y0, scale;
  a.square(level, ix, iy, x0, y0, scale);
  const std::array<Vec3d, 4>& c = corners_[index];
  const std::array<double, 4>& b = bow_[index];
  const LeafOwn node{{c[0], c[1], c[2], c[3]}, x0, y0, scale, pair_[index], {b[0], b[1], b[2], b[3]}};
  pieceAgainstDiagonal(nullptr, 0, node, x0, y0, scale, *a.diagonal, pairDiagonal_[a.node], bowDiagonal_[a.node]);
}

}  // namespace tessera::surface_tree_building
