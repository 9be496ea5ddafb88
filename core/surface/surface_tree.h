// The limit surface as a quadtree per root (a quad base face, or one quad sub-face of an n-gon,
// in Bfr's parameterization), built once per mesh and cached with its patch set. Leaves are the
// exact pieces preprocessing found (regular B-spline patches, FAS patches of the rings); every
// node knows bounds of the surface's second derivatives over its square and a box holding its
// surface, so that a request can cut the tree where ε allows without visiting finer pieces
// (docs/ADAPTIVE.md §1). A node that touches an extraordinary vertex has no finite curvature
// bound; it carries instead a bicubic stand-in g with a proven sup ‖f − g‖ ≤ r over its square:
// the ring's ACC-1 approximation at and below the ring's own level (depth tables), a
// least-squares fit of its children above it.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/base/published_slots.h"
#include "core/bounds/edge_curvature.h"
#include "core/math/bezier_net.h"
#include "core/mesh/control_mesh.h"
#include "core/rings/patch_set.h"
#include "core/surface/pair_tightening.h"

namespace tessera {

// The finest chain floor, a fraction of the bounding-box diagonal: a tree built with it serves
// every tolerance the server admits.
inline constexpr double kChainFloor = 1e-7;
// Trees for a request at relative tolerance ε are built with EV chains whose deepest stand-ins
// are within kChainBuilt·ε, rounded down to a power of ten: the planner stops in them with the
// same tiles as in the deepest tree, or a few more beside EVs (armorguy at 10⁻³ +1.8 %), for a
// fifth less preprocessing on the characters (docs/ADAPTIVE.md §1a). A tree serves planning
// tolerances down to its floor over kChainServes: ε less an encoding's reserve (at most half of
// it), which is known only once the patch set is.
inline constexpr double kChainServes = 2e-1;
inline constexpr double kChainBuilt = 1e-1;

inline constexpr uint32_t kNoNode = UINT32_MAX;

enum class NodeKind : uint8_t {
  kInternal,     // four children
  kRegularLeaf,  // payload: regular patch index
  kFasLeaf,      // payload: index into SurfaceTree::fasLeaves
  kEvChain,      // the EV's quadrant at some ring level: 3 FAS leaves and the next EV quadrant
  kEvBottom,     // the deepest EV quadrant kept: only its stand-in (payload: its EV record)
};

// Corners of a node's square: 0 = (0,0), 1 = (1,0), 2 = (1,1), 3 = (0,1) in root (u, v).
// Children: index qv * 2 + qu for the quadrant [qu/2, (qu+1)/2] × [qv/2, (qv+1)/2].
inline int quadrantOfCorner(int corner) { return corner == 0 ? 0 : corner == 1 ? 1 : corner == 2 ? 3 : 2; }

struct SurfaceNode {
  float curvature[3] = {0, 0, 0};  // M_uu, M_uv, M_vv in root units; +inf when it holds an EV
  // The node's bicubic stand-in g: sup ‖f − g‖ ≤ standInBound over the square, and g's own
  // curvature (root units). Exact pieces are their own stand-ins (bound 0).
  float standInBound = 0;
  float standInCurvature[3] = {0, 0, 0};
  // The triangle pair through the node's corners: sup ‖f ∘ φ − L‖ ≤ pairBound; sideBow[k]:
  // sup ‖f ∘ φ − chord‖ along side k (0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0), what points added
  // on that side can move the pair's interpolant. φ is the identity, the node's per-axis map or
  // its diagonal map, so each bounds the geometric distance (docs/ADAPTIVE.md §3, §3a, §3b).
  // pairDiagonal 0: the bound holds for either diagonal and any triangulation of the side
  // points; 1 + d: only for triangulations that keep diagonal d (0: corners 0–2, 1: corners 1–3).
  float pairBound = 0;
  float sideBow[4] = {0, 0, 0, 0};
  float boxMin[3] = {0, 0, 0}, boxMax[3] = {0, 0, 0};
  uint32_t firstChild = kNoNode;
  uint32_t payload = 0;  // regular patch, FAS leaf or (EV bottoms) EV record
  NodeKind kind = NodeKind::kInternal;
  uint8_t evCorners = 0;  // bit c: corner c is an extraordinary vertex inside this node
  uint8_t orientation = 0;  // leaves: Orientation::code() of the piece's (s, t) frame in the root
  uint8_t pairDiagonal = 0;

  Curvature bound() const { return {curvature[0], curvature[1], curvature[2]}; }
  Curvature standInCurvatureBound() const {
    return {standInCurvature[0], standInCurvature[1], standInCurvature[2]};
  }
  bool isLeaf() const { return firstChild == kNoNode; }
  // The pair fields as built; where the tightening is deferred (pair_tightening.h) a bound
  // above the final one: read those through pairOf.
  NodePair pairFields() const {
    return {pairBound, {sideBow[0], sideBow[1], sideBow[2], sideBow[3]}, pairDiagonal};
  }
};

// A FAS patch: sector patch k (A, B, C) of ring `ring`'s sector `sector` at FAS level `level`.
struct FasLeaf {
  uint32_t ring;
  uint16_t sector;
  uint8_t level, patch;
};

// The deepest EV quadrant kept: its stand-in (the ring's ACC-1 approximation at that level),
// which also serves to evaluate points within the chain floor of the EV.
struct EvBottom {
  std::array<Vec3, 16> g;  // Bézier net in root orientation over the node's square, from `center`
  Vec3 center;             // the ring's centre (deep quadrants are tiny: kept relative)
};

struct SurfaceRoot {
  int baseFace = 0;
  int subFace = -1;  // -1: the face is a quad
  uint32_t node = kNoNode;  // kNoNode: a hole
};

struct SurfaceTree {
  std::vector<SurfaceRoot> roots;  // in Far's ptex order
  std::vector<int> faceFirstRoot;  // base face → its first root
  std::vector<SurfaceNode> nodes;
  // Per node, for regular and FAS leaves (one bicubic piece each): docs/ADAPTIVE.md §2a's data of
  // the piece over its square, computed where a request first needs it (edgeCurvatureOf) and
  // kept; a slot costs resident memory once written.
  PublishedSlots<EdgeCurvature> edgeCurvature;
  std::vector<FasLeaf> fasLeaves;
  std::vector<EvBottom> evBottoms;
  // Each ring refined through its chain: FAS level j ≥ 1 of ring r is its refined (12n+1) set,
  // whose first 6n+1 points are the ring of level j (cer_layout.h); xyz floats relative to the
  // ring's centre, from refinedOffsets[r] on, level by level.
  std::vector<uint8_t> chainDepth;
  std::vector<size_t> refinedOffsets;
  std::vector<float> refinedLevels;
  double floor = 0;  // kChainFloor times the bounding-box diagonal
  double chainFloor = kChainFloor;  // where its EV chains stop, a fraction of the diagonal
  PairTightening tightening;  // the dearest pair bounds, computed as requests read them

  int rootOf(int baseFace, int subFace) const { return faceFirstRoot[baseFace] + (subFace < 0 ? 0 : subFace); }
  const float* refinedAtLevel(const RingSet& rings, size_t r, int level) const {
    return refinedLevels.data() + refinedOffsets[r] + size_t(level - 1) * 3 * rings.shapes[r].refinedPointCount();
  }
  const float* ringAtLevel(const RingSet& rings, size_t r, int level) const {
    return level == 0 ? rings.ringPoints(r) : refinedAtLevel(rings, r, level);
  }
  // Whether the chains go deep enough for requests down to `relativeTolerance`.
  bool serves(double relativeTolerance) const;
  size_t bytes() const;
};

// §2a's data of leaf `node`'s piece, computed on first read and kept (thread-safe: concurrent
// readers may compute it twice, the same values).
EdgeCurvature edgeCurvatureOf(const SurfaceTree& tree, const PatchSet& patches, uint32_t node);

// The chain floor to build for requests down to `finestRelativeTolerance` (0: any request).
double chainFloorFor(double finestRelativeTolerance);

// Builds the tree for a patch set. Each EV chain goes down until its stand-in bound is below
// `chainFloor` times the bounding-box diagonal (or the depth tables end): deeper chains serve
// finer requests and cost more to build (the cold path, docs/ADAPTIVE.md §1a).
// `checkpoint` (may be empty) is called for every ring and root and may throw to abandon the build.
SurfaceTree buildSurfaceTree(const PatchSet& patches, const ControlMesh& mesh, const std::function<void()>& checkpoint,
                             double chainFloor = kChainFloor);

// The square of a piece domain inside its root: level, position, and how (s, t) sits in (u, v).
struct RootSquare {
  int level = 0;
  uint64_t ix = 0, iy = 0;
  Orientation orientation;
};
RootSquare rootSquareOf(const PatchDomain& domain);

}  // namespace tessera
