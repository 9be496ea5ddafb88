// The flat pair bound (docs/ADAPTIVE.md §3d) against OpenSubdiv's limit surface: on the rook's
// roots that are one exact piece, the pair through a root's corners (either diagonal) and a
// triangulation with points on every side are within the bound both ways, measured: surface
// samples against the triangles (closest points), triangle samples projected onto the surface.
#include "core/bounds/flat_pair_bound.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "core/math/bicubic.h"
#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "core/surface/adaptive_surface.h"
#include "core/surface/surface_evaluation.h"
#include "reference/limit_projection.h"
#include "reference/models.h"
#include "reference/triangle_bvh.h"

namespace tessera {
namespace {

struct Vertex {
  double u, v;
  Vec3d p;
};
using Triangle = std::array<Vertex, 3>;

// The two-sided distance between one root's limit surface and triangles whose vertices lie on it.
double twoSidedDistance(const testing::LimitSurface& surface, int domain,
                        const std::vector<Triangle>& triangles) {
  constexpr int kSamples = 16;
  double worst = 0;
  for (int i = 0; i <= kSamples; ++i) {
    for (int j = 0; j <= kSamples; ++j) {
      Vec3d f;
      surface.evaluate(domain, double(i) / kSamples, double(j) / kSamples, f);
      double nearest = INFINITY;
      for (const Triangle& t : triangles) {
        nearest = std::min(nearest,
                           length(f - testing::closestPointOnTriangle(f, t[0].p, t[1].p, t[2].p)));
      }
      worst = std::max(worst, nearest);
    }
  }
  constexpr int kSteps = 6;
  for (const Triangle& t : triangles) {
    for (int a = 0; a <= kSteps; ++a) {
      for (int b = 0; a + b <= kSteps; ++b) {
        const double wa = double(a) / kSteps, wb = double(b) / kSteps, wc = 1 - wa - wb;
        const Vec3d p = t[0].p * wa + t[1].p * wb + t[2].p * wc;
        const double u = t[0].u * wa + t[1].u * wb + t[2].u * wc,
                     v = t[0].v * wa + t[1].v * wb + t[2].v * wc;
        // An upper bound of the distance (a local minimum), so this cannot pass by luck.
        worst = std::max(
            worst,
            testing::projectInDomain(surface, p, domain, u, v, 1e-9 * surface.diagonal()).distance);
      }
    }
  }
  return worst;
}

// The plane's own square, net points at (i/3, j/3, 0), with side v = 0 bulging outward in the
// plane: its inner control points moved by −δ in y, so the side curve reaches 3δ/4 below the
// chord at u = ½ (the Bernstein weights 3/8 + 3/8). The pair misses that strip, so the distance
// is in the plane alone: the bound must count it (the height alone is 0).
// The rook, its patch set and OpenSubdiv's limit surface of it, built once for the tests below.
struct Rook {
  Rook()
      : mesh(readObjFile(testing::modelsDir() + "/opensubdiv-shapes/catmark_rook.obj")),
        set(buildPatchSet(mesh)),
        surface(mesh),
        slack(testing::LimitSurface::kRelativeAccuracy * surface.diagonal()) {}
  ControlMesh mesh;
  PatchSet set;
  testing::LimitSurface surface;
  double slack;
};

const Rook& rook() {
  static const Rook instance;
  return instance;
}

Vertex vertexAt(const testing::LimitSurface& surface, int domain, double u, double v) {
  Vertex out{u, v, {}};
  surface.evaluate(domain, u, v, out.p);
  return out;
}

// A root's corners and three points a side, in order around it from corner `from`, fanned from
// that corner: a triangulation of side points that keeps the diagonal through it.
std::vector<Triangle> sideFan(const testing::LimitSurface& surface, int domain, int from) {
  static constexpr double kCorner[5][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
  std::vector<Vertex> boundary;
  for (int side = 0; side < 4; ++side) {
    const int k = (from + side) % 4;
    for (int step = 0; step < 4; ++step) {
      boundary.push_back(vertexAt(surface, domain,
                                  kCorner[k][0] + (kCorner[k + 1][0] - kCorner[k][0]) * step / 4,
                                  kCorner[k][1] + (kCorner[k + 1][1] - kCorner[k][1]) * step / 4));
    }
  }
  std::vector<Triangle> fan;
  for (size_t k = 1; k + 1 < boundary.size(); ++k)
    fan.push_back({boundary[0], boundary[k], boundary[k + 1]});
  return fan;
}

TEST(FlatPairBound, CountsWhatTheSidesReachOutsideThePair) {
  constexpr double kDelta = 0.01;
  BezierNet net;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i)
      net[i + 4 * j] = Vec3d(i / 3.0, j / 3.0 - (j == 0 && (i == 1 || i == 2) ? kDelta : 0), 0);
  }
  const std::optional<FlatPairBound> flat = flatPairBound(net);
  ASSERT_TRUE(flat);
  const Vec3d bulge = evaluateBezier(net.data(), 0.5, 0).position;
  EXPECT_NEAR(bulge.y, -0.75 * kDelta, 1e-12);
  // The bulge's distance from the pair (the square [0, 1]², either diagonal) is −y.
  EXPECT_GE(flat->pair, -bulge.y);
  EXPECT_GE(flat->anyTriangulation, flat->pair);
}

// A corner pushed inside the others' triangle: the projected quad is not convex, no bound.
TEST(FlatPairBound, RefusesANonConvexQuad) {
  BezierNet net;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) net[i + 4 * j] = Vec3d(i / 3.0, j / 3.0, 0);
  }
  net[15] = Vec3d(0.2, 0.2, 0);
  EXPECT_FALSE(flatPairBound(net));
}

TEST(FlatPairBound, PairsAndSidePointTriangulationsAreWithinTheBoundBothWays) {
  const testing::LimitSurface& surface = rook().surface;
  const SurfaceTree& tree = rook().set.adaptive->tree;
  const double slack = rook().slack;
  int checked = 0, taken = 0, belowEqualParameters = 0;
  double worstShare = 0;
  for (const SurfaceRoot& root : tree.roots) {
    if (root.node == kNoNode) continue;
    const SurfaceNode& node = tree.nodes[root.node];
    if (node.kind != NodeKind::kRegularLeaf && node.kind != NodeKind::kFasLeaf) continue;
    const std::optional<FlatPairBound> flat = flatPairBound(pieceNet(tree, rook().set, root.node));
    // Only bounds that could serve a tolerance (below 1 % of the diagonal).
    if (!flat || flat->anyTriangulation > 1e-2 * surface.diagonal()) continue;
    const int domain = surface.domainOf(root.baseFace, root.subFace);
    const Vertex c[4] = {vertexAt(surface, domain, 0, 0), vertexAt(surface, domain, 1, 0),
                         vertexAt(surface, domain, 1, 1), vertexAt(surface, domain, 0, 1)};
    const std::vector<Triangle> pairs[2] = {{{c[0], c[1], c[2]}, {c[0], c[2], c[3]}},
                                            {{c[0], c[1], c[3]}, {c[1], c[2], c[3]}}};
    for (const auto& pair : pairs) {
      const double measured = twoSidedDistance(surface, domain, pair);
      EXPECT_LE(measured, flat->pair + slack) << "face " << root.baseFace;
      worstShare = std::max(worstShare, measured / flat->pair);
    }
    const double measured = twoSidedDistance(surface, domain, sideFan(surface, domain, 0));
    EXPECT_LE(measured, flat->anyTriangulation + slack) << "face " << root.baseFace;
    worstShare = std::max(worstShare, measured / flat->anyTriangulation);
    ++checked;
    if (std::abs(pairOf(tree, rook().set, root.node).pair - flat->pair) > 1e-6 * flat->pair) continue;
    ++taken;
    // At equal parameters the pair is farther from the surface than the bound: the bound is not
    // a parametric one (the slivers beside the rook's semi-sharp creases).
    Vec3d f;
    surface.evaluate(domain, 0.5, 0.125, f);
    const Vec3d l = c[0].p + (c[1].p - c[0].p) * 0.5 + (c[2].p - c[1].p) * 0.125;
    belowEqualParameters += length(f - l) > flat->pair + slack;
  }
  EXPECT_GT(checked, 0);
  EXPECT_GT(taken, 0);
  EXPECT_GT(belowEqualParameters, 0);
  std::printf(
      "rook: %d one-piece roots checked, %d keep the flat bound, %d of them below the distance at "
      "equal "
      "parameters; worst measured / bound %.2f\n",
      checked, taken, belowEqualParameters, worstShare);
}

// What the tree stores for every rook root, one piece or many (its pair bound, side bows and the
// diagonal they need, §3, §3d): the fan of its corners and three points a side from the corner on
// that diagonal (which keeps it) is within the pair bound plus the largest bow both ways.
TEST(FlatPairBound, StoredBoundsHoldForEveryRootsSideTriangulation) {
  const testing::LimitSurface& surface = rook().surface;
  const SurfaceTree& tree = rook().set.adaptive->tree;
  const double slack = rook().slack;
  int checked = 0, severalPieces = 0;
  double worstShare = 0;
  for (const SurfaceRoot& root : tree.roots) {
    if (root.node == kNoNode) continue;
    const SurfaceNode& node = tree.nodes[root.node];
    const NodePair stored = pairOf(tree, rook().set, root.node);
    const double bound = stored.pair + *std::max_element(stored.bows, stored.bows + 4);
    if (bound > 1e-2 * surface.diagonal()) continue;
    const int domain = surface.domainOf(root.baseFace, root.subFace);
    const double measured =
        twoSidedDistance(surface, domain, sideFan(surface, domain, stored.diagonal == 2 ? 1 : 0));
    EXPECT_LE(measured, bound + slack) << "face " << root.baseFace << " sub-face " << root.subFace;
    worstShare = std::max(worstShare, measured / bound);
    ++checked;
    severalPieces += !node.isLeaf();
  }
  EXPECT_GT(severalPieces, 100);
  std::printf("rook: %d roots checked (%d of several pieces); worst measured / bound %.2f\n",
              checked, severalPieces, worstShare);
}

}  // namespace
}  // namespace tessera
