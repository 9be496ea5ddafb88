// The pair bounds a request computes on first read (core/surface/pair_tightening.h), direct and
// tightened: the same whatever order and however many threads read them, each stage never looser
// than the one before it nor than the bounds the tree was built with, never below the lower bound
// the planner skips by, and a GLB that does not depend on which requests came first.
#include "core/surface/pair_tightening.h"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "core/pipeline/tessellate.h"
#include "core/surface/adaptive_surface.h"
#include "reference/models.h"

namespace tessera {
namespace {

// Semi-sharp creases, extraordinary vertices and boundaries: every kind of deferred node.
ControlMesh cubes() { return readObjFile(testing::modelsDir() + "/opensubdiv-shapes/catmark_cubes_semisharp.obj"); }

// The same vertices, bit for bit, and the same triangles.
bool sameMesh(const TriangleMesh& a, const TriangleMesh& b) {
  return a.indices == b.indices && a.positions.size() == b.positions.size() &&
         std::memcmp(a.positions.data(), b.positions.data(), a.positions.size() * sizeof(Vec3)) == 0;
}

bool samePair(const NodePair& a, const NodePair& b) {
  return a.pair == b.pair && std::memcmp(a.bows, b.bows, sizeof a.bows) == 0 && a.diagonal == b.diagonal;
}

TEST(PairTightening, TheSameBoundsInAnyOrderAndOnManyThreads) {
  const ControlMesh mesh = cubes();
  const PatchSet forward = buildPatchSet(mesh), backward = buildPatchSet(mesh);
  const SurfaceTree& a = forward.adaptive->tree;
  const SurfaceTree& b = backward.adaptive->tree;
  const size_t n = a.nodes.size();
  std::vector<NodePair> inOrder(n), concurrent(n), directInOrder(n), directConcurrent(n);
  for (size_t i = 0; i < n; ++i) inOrder[i] = pairOf(a, forward, uint32_t(i));
  for (size_t i = 0; i < n; ++i) directInOrder[i] = directPairOf(a, forward, uint32_t(i));
  // Backwards, the direct bounds of the deep nodes first, then their ancestors'.
  tbb::parallel_for(size_t(0), n, [&](size_t k) {
    const uint32_t i = uint32_t(n - 1 - k);
    directConcurrent[i] = directPairOf(b, backward, i);
    concurrent[i] = pairOf(b, backward, i);
  });
  int leaves = 0, internal = 0, tighter = 0;
  for (size_t i = 0; i < n; ++i) {
    ASSERT_TRUE(samePair(directInOrder[i], directConcurrent[i])) << "node " << i;
    ASSERT_TRUE(samePair(inOrder[i], concurrent[i])) << "node " << i;
    const PairTightening::Deferred deferred = a.tightening.deferred(uint32_t(i));
    leaves += deferred == PairTightening::Deferred::kLeaf;
    internal += deferred == PairTightening::Deferred::kInternal;
    tighter += inOrder[i].pair < directInOrder[i].pair;
  }
  EXPECT_GT(leaves, 0);
  EXPECT_GT(internal, 0);
  EXPECT_GT(tighter, 0);  // otherwise nothing here was tested
}

// Tightening only takes off, and never goes below the lower bound by which the planner decides
// that a node's pair cannot serve without tightening it.
TEST(PairTightening, NeverLooserAndNeverBelowTheLowerBound) {
  const ControlMesh mesh = cubes();
  const PatchSet set = buildPatchSet(mesh);
  const SurfaceTree& tree = set.adaptive->tree;
  int directs = 0;
  for (uint32_t i = 0; i < tree.nodes.size(); ++i) {
    const NodePair direct = directPairOf(tree, set, i);
    const NodePair tight = pairOf(tree, set, i);
    // An exact leaf's fields wait for a request: +∞ until then, never read as a bound.
    if (tree.nodes[i].kind == NodeKind::kRegularLeaf || tree.nodes[i].kind == NodeKind::kFasLeaf) {
      EXPECT_EQ(tree.nodes[i].pairBound, INFINITY) << "node " << i;
      EXPECT_LT(direct.pair, INFINITY) << "node " << i;
    }
    EXPECT_LE(direct.pair, tree.nodes[i].pairBound) << "node " << i;
    EXPECT_LE(tight.pair, direct.pair) << "node " << i;
    for (int k = 0; k < 4; ++k) EXPECT_LE(direct.bows[k], tree.nodes[i].sideBow[k]) << "node " << i;
    // An internal node's direct bounds always wait for a request.
    const bool internal = !tree.nodes[i].isLeaf();
    const bool deferred = internal || tree.tightening.deferred(i) != PairTightening::Deferred::kNone;
    if (!deferred) continue;
    directs += internal && direct.pair < tree.nodes[i].pairBound;
    EXPECT_TRUE(tree.tightening.mayReach(i, tight.pair)) << "node " << i;
  }
  EXPECT_GT(directs, 0);  // the pieces took off something from the stand-ins' bounds somewhere
}

// A tightening stopped at a limit says only what the whole one would: none exactly where the
// tightened pair is above the limit, else the same bounds; and afterwards the node is known not
// to reach any ε up to that limit.
// The nodes of `tree` at most `depth` levels below a root.
std::vector<uint32_t> nodesDownTo(const SurfaceTree& tree, int depth) {
  std::vector<uint32_t> out, level;
  for (const SurfaceRoot& root : tree.roots) {
    if (root.node != kNoNode) level.push_back(root.node);
  }
  for (int d = 0; d <= depth && !level.empty(); ++d) {
    out.insert(out.end(), level.begin(), level.end());
    std::vector<uint32_t> next;
    for (uint32_t i : level) {
      if (tree.nodes[i].isLeaf()) continue;
      for (int q = 0; q < 4; ++q) next.push_back(tree.nodes[i].firstChild + q);
    }
    level = std::move(next);
  }
  return out;
}

void expectStopsAgree(const ControlMesh& mesh, int depth, const std::vector<double>& relativeLimits) {
  const PatchSet whole = buildPatchSet(mesh);
  const SurfaceTree& reference = whole.adaptive->tree;
  const double diagonal = length(Vec3d(whole.boundsMax) - Vec3d(whole.boundsMin));
  int stopped = 0, kept = 0;
  for (double relative : relativeLimits) {
    const PatchSet set = buildPatchSet(mesh);
    const SurfaceTree& tree = set.adaptive->tree;
    const double limit = relative * diagonal;
    for (uint32_t i : nodesDownTo(tree, depth)) {
      if (tree.tightening.deferred(i) == PairTightening::Deferred::kNone) continue;
      const NodePair full = pairOf(reference, whole, i);
      const std::optional<NodePair> within = pairWithin(tree, set, i, limit);
      if (!within) {
        ++stopped;
        EXPECT_GT(full.pair, limit) << "node " << i;
        EXPECT_FALSE(tree.tightening.mayReach(i, limit)) << "node " << i;
        EXPECT_FALSE(tree.tightening.mayReach(i, limit / 2)) << "node " << i;
        continue;
      }
      ++kept;
      EXPECT_TRUE(samePair(*within, full)) << "node " << i << " limit " << limit;
    }
  }
  EXPECT_GT(stopped, 0);  // otherwise the stop was not tested
  EXPECT_GT(kept, 0);
}

TEST(PairTightening, StoppedAtALimitAgreesWithTheWholeTightening) { expectStopsAgree(cubes(), 64, {3e-2, 1e-2, 3e-3, 1e-3}); }

// Where §3d's flat bound is the one that brings a node within the limit (the rook's flat tops).
TEST(PairTightening, StoppedAtALimitAgreesWhereTheFlatBoundDecides) {
  // The nodes a plan reads at these limits: its deep crease strips would take minutes to tighten.
  expectStopsAgree(readObjFile(testing::modelsDir() + "/opensubdiv-shapes/catmark_rook.obj"), 3, {1e-2, 1e-3});
}

// The planner tightens what it reads: a cold request, a warm one after it, and one on a tree whose
// every node was tightened first make the same triangles.
TEST(PairTightening, TheGlbDoesNotDependOnEarlierRequests) {
  const ControlMesh mesh = cubes();
  for (double epsilon : {1e-2, 1e-3}) {
    TessellationOptions options;
    options.accuracy = Accuracy::relative(epsilon);
    const PatchSet lazy = buildPatchSet(mesh), eager = buildPatchSet(mesh);
    for (uint32_t i = 0; i < eager.adaptive->tree.nodes.size(); ++i) pairOf(eager.adaptive->tree, eager, i);
    const TriangleMesh cold = tessellate(lazy, mesh, options).mesh;
    const TriangleMesh warm = tessellate(lazy, mesh, options).mesh;
    const TriangleMesh tightened = tessellate(eager, mesh, options).mesh;
    ASSERT_GT(cold.triangleCount(), 0u);
    EXPECT_TRUE(sameMesh(cold, warm)) << epsilon;
    EXPECT_TRUE(sameMesh(cold, tightened)) << epsilon;
  }
}

}  // namespace
}  // namespace tessera
