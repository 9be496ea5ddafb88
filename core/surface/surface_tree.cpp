#include "core/surface/surface_tree.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "core/base/error.h"
#include "core/bounds/depth_bound.h"
#include "core/bounds/depth_tables.h"
#include "core/bounds/graded_pair_bound.h"
#include "core/rings/fas.h"
#include "core/rings/innermost_patch.h"
#include "core/rings/ring_patches.h"
#include "core/rings/ring_refinement.h"
#include "core/surface/surface_evaluation.h"
#include "core/surface/surface_tree_builder.h"

namespace tessera {

RootSquare rootSquareOf(const PatchDomain& d) {
  RootSquare sq;
  const double size = std::abs(d.axisS[0]) + std::abs(d.axisS[1]);
  const double minU = d.origin[0] + std::min(0.0, d.axisS[0]) + std::min(0.0, d.axisT[0]);
  const double minV = d.origin[1] + std::min(0.0, d.axisS[1]) + std::min(0.0, d.axisT[1]);
  sq.level = -std::ilogb(size);
  if (std::ldexp(1.0, -sq.level) != size) throwUnsupported("internal: a piece is not a dyadic square");
  sq.ix = uint64_t(std::llround(minU / size));
  sq.iy = uint64_t(std::llround(minV / size));
  auto sign = [](double x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); };
  sq.orientation = {sign(d.axisS[0]), sign(d.axisS[1]), sign(d.axisT[0]), sign(d.axisT[1])};
  return sq;
}

namespace surface_tree_building {

namespace {

// The corner of a square (in its root) that a piece's (s, t) origin sits on.
int originCorner(const PatchDomain& d) {
  const RootSquare sq = rootSquareOf(d);
  const double size = std::ldexp(1.0, -sq.level);
  const int cu = d.origin[0] > sq.ix * size ? 1 : 0, cv = d.origin[1] > sq.iy * size ? 1 : 0;
  return cv ? (cu ? 2 : 3) : (cu ? 1 : 0);
}

}  // namespace

void TreeBuilder::makeRoots() {
  tree_.faceFirstRoot.resize(mesh_.faceCount());
  for (int f = 0; f < mesh_.faceCount(); ++f) {
    tree_.faceFirstRoot[f] = int(tree_.roots.size());
    const int size = mesh_.faceSizes[f];
    for (int k = 0; k < (size == 4 ? 1 : size); ++k) tree_.roots.push_back({f, size == 4 ? -1 : k, kNoNode});
  }
}

// The bound of ring r's ACC-1 stand-in after `level` FAS steps, from the depth tables (c_m·‖Q₀‖)
// or the refined ring itself (c₀·‖Q_m‖, or the hull bound for kinds without tables).
namespace {

double standInBound(const RingSet& rings, size_t r, const float* ringAtLevel, int level) {
  const RingRules rules = rings.rules(r);
  double bound = boundAtDepth(rules, ringAtLevel, 0);
  if (depthCoefficients(rules) != nullptr) bound = std::min(bound, boundAtDepth(rules, rings.ringPoints(r), level));
  return bound;
}

}  // namespace

// The stand-in bound, the EV's limit and the box (world coordinates, widened by one float step)
// of ring r at `level`: every EV quadrant of the ring at that level takes them (ringStandIn, setBox).
TreeBuilder::RingLevel TreeBuilder::ringLevel(size_t r, const float* ring, int level) const {
  const RingSet& rings = patches_.rings;
  const RingRules rules = rings.rules(r);
  RingLevel shared;
  shared.bound = standInBound(rings, r, ring, level);
  shared.limit = extraordinaryLimit<Vec3d>(rules, [ring](int index) {
    return Vec3d(ring[3 * index], ring[3 * index + 1], ring[3 * index + 2]);
  });
  const Vec3 c = rings.centers[r];
  for (int a = 0; a < 3; ++a) shared.boxMin[a] = shared.boxMax[a] = ring[a] + c[a];
  for (int p = 0; p < rings.shapes[r].ringPointCount(); ++p) {
    for (int a = 0; a < 3; ++a) {
      const float x = ring[3 * p + a] + c[a];
      shared.boxMin[a] = std::min(shared.boxMin[a], x), shared.boxMax[a] = std::max(shared.boxMax[a], x);
    }
  }
  for (int a = 0; a < 3; ++a) {
    shared.boxMin[a] = std::nextafter(shared.boxMin[a], -kInfinity);
    shared.boxMax[a] = std::nextafter(shared.boxMax[a], kInfinity);
  }
  return shared;
}

// Each ring is refined until its stand-in bound drops below the floor (or the tables end); the
// refined sets of every level are kept, for the FAS leaves' nets.
void TreeBuilder::refineRings() {
  const RingSet& rings = patches_.rings;
  tree_.chainDepth.resize(rings.size());
  ringLevels_.assign(rings.size(), {});
  std::vector<std::vector<float>> levels(rings.size());
  tbb::parallel_for(size_t(0), rings.size(), [&](size_t r) {
    checkpointNow();
    const RingRules rules = rings.rules(r);
    const size_t refinedFloats = 3 * size_t(rules.shape.refinedPointCount());
    std::vector<float>& kept = levels[r];
    auto ringOf = [&](int level) { return level == 0 ? rings.ringPoints(r) : kept.data() + (level - 1) * refinedFloats; };
    std::vector<RingLevel>& shared = ringLevels_[r];
    int depth = 0;
    for (;;) {
      shared.push_back(ringLevel(r, ringOf(depth), depth));
      if (depth == kMaxTableDepth || shared.back().bound <= chainFloor_) break;
      kept.resize((depth + 1) * refinedFloats);
      refineRingStep<3>(rules, ringOf(depth), kept.data() + depth * refinedFloats);
      ++depth;
    }
    tree_.chainDepth[r] = uint8_t(depth);
  });
  tree_.refinedOffsets.resize(rings.size());
  for (size_t r = 0; r < rings.size(); ++r) {
    tree_.refinedOffsets[r] = tree_.refinedLevels.size();
    tree_.refinedLevels.insert(tree_.refinedLevels.end(), levels[r].begin(), levels[r].end());
  }
}

std::vector<std::vector<Item>> TreeBuilder::collectItems() const {
  std::vector<std::vector<Item>> items(tree_.roots.size());
  const RegularPatches& regular = patches_.regular;
  for (size_t p = 0; p < regular.size(); ++p) {
    const PatchDomain& d = regular.domains[p];
    const RootSquare sq = rootSquareOf(d);
    items[tree_.rootOf(d.baseFace, d.subFace)].push_back({sq.level, sq.ix, sq.iy, false, uint32_t(p), 0});
  }
  const RingSet& rings = patches_.rings;
  for (size_t r = 0; r < rings.size(); ++r) {
    for (int i = 0; i < rings.shapes[r].sectors; ++i) {
      const size_t k = rings.sectorOffsets[r] + i;
      if (!rings.sectorOwned[k]) continue;
      const PatchDomain& d = rings.sectorDomains[k];
      const RootSquare sq = rootSquareOf(d);
      items[tree_.rootOf(d.baseFace, d.subFace)].push_back({sq.level, sq.ix, sq.iy, true, uint32_t(r), i});
    }
  }
  return items;
}

uint32_t TreeBuilder::allocateChildren() {
  const uint32_t first = uint32_t(tree_.nodes.size());
  tree_.nodes.resize(tree_.nodes.size() + 4);
  chainOf_.resize(tree_.nodes.size(), -1);
  return first;
}

void TreeBuilder::fill(uint32_t slot, int level, uint64_t ix, uint64_t iy, std::vector<Item>& items) {
  if (items.empty()) throwUnsupported("internal: a part of a face is covered by no piece");
  if (items.size() == 1 && items[0].level == level) {
    const Item& item = items[0];
    if (item.sector) return fillChain(slot, item.index, item.ringSector, 0);
    tree_.nodes[slot].kind = NodeKind::kRegularLeaf;
    tree_.nodes[slot].payload = item.index;
    tree_.nodes[slot].orientation = rootSquareOf(patches_.regular.domains[item.index]).orientation.code();
    return;
  }
  std::vector<Item> quadrants[4];
  for (const Item& item : items) {
    if (item.level <= level) throwUnsupported("internal: pieces of a face overlap");
    const int bit = item.level - level - 1;
    quadrants[((item.iy >> bit) & 1) * 2 + ((item.ix >> bit) & 1)].push_back(item);
  }
  items.clear();
  items.shrink_to_fit();
  const uint32_t first = allocateChildren();
  tree_.nodes[slot].firstChild = first;
  for (int q = 0; q < 4; ++q) fill(first + q, level + 1, 2 * ix + (q & 1), 2 * iy + (q >> 1), quadrants[q]);
}

// The EV quadrant of ring `ring`'s sector at chain level j and, above the chain's depth, the
// next EV quadrant and the three FAS patches of level j + 1 below it.
void TreeBuilder::fillChain(uint32_t slot, uint32_t ring, int sector, int chainLevel) {
  const RingSet& rings = patches_.rings;
  const PatchDomain& sectorDomain = rings.sectorDomains[rings.sectorOffsets[ring] + sector];
  const int evCorner = originCorner(sectorDomain);
  const bool bottom = chainLevel >= tree_.chainDepth[ring];
  tree_.nodes[slot].kind = bottom ? NodeKind::kEvBottom : NodeKind::kEvChain;
  tree_.nodes[slot].evCorners = uint8_t(1 << evCorner);
  chainOf_[slot] = int32_t(chainSteps_.size());
  chainSteps_.push_back({ring, sector, chainLevel});
  if (bottom) {
    tree_.nodes[slot].payload = uint32_t(tree_.evBottoms.size());
    tree_.evBottoms.emplace_back();
    return;
  }
  const uint32_t first = allocateChildren();
  tree_.nodes[slot].firstChild = first;
  fillChain(first + quadrantOfCorner(evCorner), ring, sector, chainLevel + 1);
  const double size = std::ldexp(1.0, -(chainLevel + 1));
  const RootSquare parent = rootSquareOf(sectorDomain.restrict(0, 0, 2 * size));
  for (int k = 0; k < kPatchesPerSector; ++k) {
    int x0, y0;
    sectorPatchOrigin(k, x0, y0);
    const RootSquare sq = rootSquareOf(sectorDomain.restrict(x0 * size, y0 * size, size));
    const int q = int((sq.iy - 2 * parent.iy) * 2 + (sq.ix - 2 * parent.ix));
    SurfaceNode& leaf = tree_.nodes[first + q];
    leaf.kind = NodeKind::kFasLeaf;
    leaf.payload = uint32_t(tree_.fasLeaves.size());
    leaf.orientation = sq.orientation.code();
    tree_.fasLeaves.push_back({ring, uint16_t(sector), uint8_t(chainLevel + 1), uint8_t(k)});
  }
}

BezierNet TreeBuilder::leafNet(const SurfaceNode& node) const {
  return pieceNet(tree_, patches_, uint32_t(&node - tree_.nodes.data()));
}

namespace {

void setCurvature(float out[3], const Curvature& m) {
  out[0] = roundUp(m.uu), out[1] = roundUp(m.uv), out[2] = roundUp(m.vv);
}

}  // namespace

NodeFit TreeBuilder::summarizeLeaf(SurfaceNode& node, int level) const {
  NodeFit fit;
  fit.g = leafNet(node);
  for (int c = 0; c < 4; ++c) fit.corners[c] = fit.g[kCornerIndex[c]];
  setCurvature(node.curvature, netCurvature(fit.g.data()).scaled(std::ldexp(1.0, 2 * level)));
  for (int a = 0; a < 3; ++a) {
    double lo = fit.g[0][a], hi = lo;
    for (const Vec3d& p : fit.g) lo = std::min(lo, p[a]), hi = std::max(hi, p[a]);
    node.boxMin[a] = std::nextafter(float(lo), -kInfinity);
    node.boxMax[a] = std::nextafter(float(hi), kInfinity);
  }
  return fit;
}

// An EV quadrant's ACC-1 stand-in from the ring at its level, with the depth tables' bound. Its
// corners are exact: the EV corner is the limit position, the outer edges are taken from the
// neighbouring B-spline patches (innermost_patch.h).
NodeFit TreeBuilder::ringStandIn(const ChainStep& step, int) const {
  const RingSet& rings = patches_.rings;
  const RingRules rules = rings.rules(step.ring);
  const float* ring = tree_.ringAtLevel(rings, step.ring, step.level);
  // In double, relative to the centre, then moved: deep rings are tiny next to the model.
  auto fetch = [ring](int index) { return Vec3d(ring[3 * index], ring[3 * index + 1], ring[3 * index + 2]); };
  Vec3d g[16];
  innermostBezier<Vec3d>(rules, step.sector, fetch, g, &ringLevels_[step.ring][step.level].limit);
  for (Vec3d& p : g) p += Vec3d(rings.centers[step.ring]);
  const PatchDomain& sectorDomain = rings.sectorDomains[rings.sectorOffsets[step.ring] + step.sector];
  NodeFit fit;
  fit.g = orientNet(g, rootSquareOf(sectorDomain).orientation);
  for (int c = 0; c < 4; ++c) fit.corners[c] = fit.g[kCornerIndex[c]];
  fit.r = ringLevels_[step.ring][step.level].bound * (1 + 1e-5) + 1e-6 * floor_;
  return fit;
}

// The least-squares bicubic of four children, r = max_k (r_k + hull distance between child k's
// stand-in and the fit's quadrant k); the corners are the children's.
NodeFit TreeBuilder::fitChildren(const NodeFit children[4]) const {
  BezierNet quadrants[4];
  for (int q = 0; q < 4; ++q) quadrants[q] = children[q].g;
  NodeFit fit;
  fit.g = coarsenNets(quadrants);
  BezierNet fitted[4];
  quadrantNets(fit.g, std::array<BezierNet*, 4>{&fitted[0], &fitted[1], &fitted[2], &fitted[3]}.data());
  for (int q = 0; q < 4; ++q) fit.r = std::max(fit.r, children[q].r + netDistance(quadrants[q], fitted[q]));
  for (int c = 0; c < 4; ++c) fit.corners[c] = children[quadrantOfCorner(c)].corners[c];
  return fit;
}

// An EV quadrant's box: the surface over it lies in the hull of its ring (Catmull-Clark's masks
// are convex combinations). Other nodes: the union of their children's boxes.
void TreeBuilder::setBox(uint32_t index, const ChainStep* step) {
  SurfaceNode& node = tree_.nodes[index];
  if (step != nullptr) {
    const RingLevel& shared = ringLevels_[step->ring][step->level];
    std::copy(shared.boxMin, shared.boxMin + 3, node.boxMin);
    std::copy(shared.boxMax, shared.boxMax + 3, node.boxMax);
    return;
  }
  for (int q = 0; q < 4; ++q) {
    const SurfaceNode& child = tree_.nodes[node.firstChild + q];
    for (int a = 0; a < 3; ++a) {
      node.boxMin[a] = q == 0 ? child.boxMin[a] : std::min(node.boxMin[a], child.boxMin[a]);
      node.boxMax[a] = q == 0 ? child.boxMax[a] : std::max(node.boxMax[a], child.boxMax[a]);
    }
  }
}

StandInPair standInPair(const BezierNet& g, const Vec3d corners[4], double r) {
  const Vec3d twist = corners[0] - corners[1] + corners[2] - corners[3];
  // g's deviation from B over the square (split along either diagonal) and from each side's chord.
  const double split = splitNetDistance(g, bilinearNet(corners));
  const std::array<double, 4> chords = chordBows(g, corners);
  StandInPair out;
  out.fields.pair = roundUp((r + split + length(twist) / 4) * (1 + 1e-9));
  for (int side = 0; side < 4; ++side) out.fields.bows[side] = roundUp((r + chords[side]) * (1 + 1e-9));
  out.own = r + split;
  for (int side = 0; side < 4; ++side) out.ownBows[side] = r + chords[side];
  return out;
}

// The stand-in's bound and curvature, and but for an exact leaf the pair fields through it: an
// exact leaf's wait for a request (directBoundsOf: most leaves of a creased sheet are never
// read), and its fields say +∞ until then, so that nothing reads them as a bound.
void TreeBuilder::setStandIn(SurfaceNode& node, const NodeFit& fit, int level) const {
  node.standInBound = roundUp(fit.r);
  // An exact leaf is its own stand-in: its curvature is g's (summarizeLeaf).
  if (node.kind == NodeKind::kRegularLeaf || node.kind == NodeKind::kFasLeaf) {
    std::copy(node.curvature, node.curvature + 3, node.standInCurvature);
    node.pairBound = kInfinity;
    std::fill(node.sideBow, node.sideBow + 4, kInfinity);
    return;
  }
  setCurvature(node.standInCurvature, netCurvature(fit.g.data()).scaled(std::ldexp(1.0, 2 * level)));
  const NodePair fields = standInPair(fit.g, fit.corners, fit.r).fields;
  node.pairBound = fields.pair;
  std::copy(fields.bows, fields.bows + 4, node.sideBow);
}

// Bounds bottom-up. EV quadrants of a chain take the better of the ring's ACC-1 stand-in and
// the fit of their children; the deepest keeps the former (and its net, for evaluation).
NodeFit TreeBuilder::summarize(uint32_t index, int level) {
  SurfaceNode& self = tree_.nodes[index];
  if (self.kind == NodeKind::kRegularLeaf || self.kind == NodeKind::kFasLeaf) {
    NodeFit fit = summarizeLeaf(self, level);
    for (int c = 0; c < 4; ++c) tree_.tightening.corners[index][c] = fit.corners[c];
    setStandIn(tree_.nodes[index], fit, level);
    tree_.tightening.defer(index, PairTightening::Deferred::kLeaf, pairLowerBound(fit.g));
    return fit;
  }
  const ChainStep* step = chainOf_[index] >= 0 ? &chainSteps_[chainOf_[index]] : nullptr;
  NodeFit fit;
  if (self.kind == NodeKind::kEvBottom) {
    fit = ringStandIn(*step, level);
    EvBottom& bottom = tree_.evBottoms[self.payload];
    bottom.center = patches_.rings.centers[step->ring];
    for (int k = 0; k < 16; ++k) bottom.g[k] = Vec3(fit.g[k] - Vec3d(bottom.center));
  } else {
    NodeFit children[4];
    for (int q = 0; q < 4; ++q) children[q] = summarize(tree_.nodes[index].firstChild + q, level + 1);
    fit = fitChildren(children);
    if (step != nullptr) {
      NodeFit ring = ringStandIn(*step, level);
      if (ring.r < fit.r) fit = ring;
    }
  }
  SurfaceNode& node = tree_.nodes[index];
  for (int c = 0; c < 4; ++c) tree_.tightening.corners[index][c] = fit.corners[c];
  setBox(index, node.kind == NodeKind::kInternal ? nullptr : step);
  if (node.kind == NodeKind::kInternal) {
    Curvature m;
    for (int q = 0; q < 4; ++q) {
      const SurfaceNode& child = tree_.nodes[node.firstChild + q];
      m = m.max(child.bound());
      for (int corner = 0; corner < 4; ++corner) {
        if (quadrantOfCorner(corner) == q && (child.evCorners >> corner & 1)) node.evCorners |= uint8_t(1 << corner);
      }
    }
    setCurvature(node.curvature, m);
  } else {
    for (float& m : node.curvature) m = kInfinity;
  }
  setStandIn(node, fit, level);
  if (node.isLeaf()) {
    double r;
    // The stand-in as evaluation reads it: in floats, with the bound rounded up.
    const BezierNet g = netOrStandIn(tree_, patches_, index, r);
    Vec3d corners[4];
    for (int k = 0; k < 4; ++k) corners[k] = g[kCornerIndex[k]];
    keepOwn(index, standInPair(g, corners, r));
  } else {
    deferPairs(index);
  }
  return fit;
}

// An EV bottom's own bounds at equal parameters (its stand-in as evaluation reads it, in floats,
// against the bilinear of its corners, grown by r): its ancestors' direct bounds start from them
// (direct_pair_bounds.cpp). An exact leaf's are computed where first read (directBoundsOf).
void TreeBuilder::keepOwn(uint32_t index, const StandInPair& pair) {
  tree_.tightening.publishDirect(index, leafDirectBounds(tree_.nodes[index].pairFields(), pair.own, pair.ownBows));
}

// An internal node's pair fields are its stand-in's (setStandIn) until a request reads them:
// its direct bounds wait, and where the node is coarser than kDiagonalFloor so do its diagonal
// map (§3b) and flat projection (§3d).
void TreeBuilder::deferPairs(uint32_t index) {
  const SurfaceNode& node = tree_.nodes[index];
  const std::array<Vec3d, 4>& c = tree_.tightening.corners[index];
  // The surface's centre is the corner all four children share.
  const double lower = pairLowerBound(c.data(), tree_.tightening.corners[node.firstChild][2]);
  tree_.tightening.deferDirect(index, lower);
  if (node.pairBound > kDiagonalFloor * floor_) tree_.tightening.defer(index, PairTightening::Deferred::kInternal, lower);
}

SurfaceTree TreeBuilder::build(double chainFloor) {
  const double diagonal = length(Vec3d(patches_.boundsMax) - Vec3d(patches_.boundsMin));
  floor_ = kChainFloor * (diagonal > 0 ? diagonal : 1.0);
  chainFloor_ = chainFloor * (diagonal > 0 ? diagonal : 1.0);
  tree_.floor = floor_;
  tree_.chainFloor = chainFloor;
  makeRoots();
  refineRings();
  std::vector<std::vector<Item>> items = collectItems();
  for (size_t root = 0; root < tree_.roots.size(); ++root) {
    if (items[root].empty()) continue;
    const uint32_t slot = uint32_t(tree_.nodes.size());
    tree_.nodes.emplace_back();
    chainOf_.push_back(-1);
    tree_.roots[root].node = slot;
    fill(slot, 0, 0, 0, items[root]);
  }
  tree_.edgeCurvature = PublishedSlots<EdgeCurvature>(tree_.nodes.size());
  tree_.tightening = PairTightening(tree_.nodes.size());
  tree_.tightening.floor = floor_;
  // Roots are independent: every slot they write was allocated above.
  tbb::parallel_for(size_t(0), tree_.roots.size(), [&](size_t r) {
    const uint32_t root = tree_.roots[r].node;
    if (root == kNoNode) return;
    checkpointNow();
    summarize(root, 0);
  });
  return std::move(tree_);
}

}  // namespace surface_tree_building

size_t SurfaceTree::bytes() const {
  return sizeof(*this) + roots.size() * sizeof(SurfaceRoot) + faceFirstRoot.size() * sizeof(int) +
         nodes.size() * (sizeof(SurfaceNode) + PublishedSlots<EdgeCurvature>::kBytesPerSlot) + fasLeaves.size() * sizeof(FasLeaf) +
         evBottoms.size() * sizeof(EvBottom) + chainDepth.size() + refinedOffsets.size() * sizeof(size_t) +
         refinedLevels.size() * sizeof(float) + tightening.bytes();
}

SurfaceTree buildSurfaceTree(const PatchSet& patches, const ControlMesh& mesh, const std::function<void()>& checkpoint,
                             double chainFloor) {
  return surface_tree_building::TreeBuilder(patches, mesh, checkpoint).build(chainFloor);
}

EdgeCurvature edgeCurvatureOf(const SurfaceTree& tree, const PatchSet& patches, uint32_t node) {
  if (tree.edgeCurvature.known(node)) return tree.edgeCurvature[node];
  const EdgeCurvature edges = edgeCurvature(pieceNet(tree, patches, node));
  tree.edgeCurvature.publish(node, edges);
  return edges;
}

double chainFloorFor(double finestRelativeTolerance) {
  if (!(finestRelativeTolerance > 0)) return kChainFloor;
  return std::max(kChainFloor, std::pow(10.0, std::floor(std::log10(kChainBuilt * finestRelativeTolerance))));
}

bool SurfaceTree::serves(double relativeTolerance) const {
  return chainFloor <= std::max(kChainFloor, kChainServes * relativeTolerance) * (1 + 1e-9);
}

}  // namespace tessera
