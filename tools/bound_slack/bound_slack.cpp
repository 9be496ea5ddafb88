// tessera-bound-slack: how far the planner's proven bounds sit above the measured distance, for the
// grid tiles of an adaptive tessellation (docs/ADAPTIVE.md §8). A grid tile here is a tile of at
// least two cells (not cell-wise) over one leaf piece without an extraordinary vertex. For each:
// its bound; the distance of the surface over it from the output triangles of its root (7 × 7
// samples a cell, each to its nearest such triangle: one side of the two-sided distance the bound
// covers; other roots are left out so that the far side of a thin wall does not count); and, for
// comparison, §2's FMM86 form with only the normal component of the piece's second
// derivatives, and the estimate of docs/ADAPTIVE.md §8's route (the normal component against the
// normal at the tile's centre, plus its tilt times §2, or the largest deviation of a cell's side
// or diagonal across its chord; all sampled: estimates of what bounds blind to the
// parameterization's in-plane distortion could reach, not bounds).
//
//   build/tools/tessera-bound-slack ../shared/models/bigguy.obj 1e-3
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "core/adaptive_surface.h"
#include "core/adaptive_tessellator.h"
#include "core/bicubic.h"
#include "core/obj_reader.h"
#include "core/surface_evaluation.h"
#include "tests/support/triangle_bvh.h"  // closestPointOnTriangle

namespace tessera {
namespace {

constexpr int kCellSamples = 6;     // intervals a cell side is sampled at
constexpr int kCurvatureSamples = 12;

struct TileFigures {
  double bound, measured, normalForm, route;
};

// Second derivatives (tile units) and the frame at one point of a leaf's net.
struct LocalShape {
  Vec3d fu, fv, fuu, fuv, fvv, normal;
};

// The part of x across the unit direction d.
Vec3d across(const Vec3d& x, const Vec3d& d) { return x - d * dot(x, d); }

// The largest distance of the surface over the tile's cells from the given triangles.
double measuredDistance(SurfaceEvaluator& evaluator, const TriangleMesh& mesh, const std::vector<uint32_t>& triangles,
                        const NodeSquare& root, const Tile& tile) {
  const double s = tile.size(), u0 = double(tile.ix) * s, v0 = double(tile.iy) * s;
  const int nu = tile.ru * kCellSamples, nv = tile.rv * kCellSamples;
  const auto corner = [&](uint32_t t, int k) { return Vec3d(mesh.positions[mesh.indices[3 * t + uint32_t(k)]]); };
  double worst = 0;
  for (int j = 0; j <= nv; ++j) {
    for (int i = 0; i <= nu; ++i) {
      const Vec3d p = evaluator.evaluate(root, u0 + s * i / nu, v0 + s * j / nv).position;
      double nearest = INFINITY;
      for (const uint32_t t : triangles) {
        nearest = std::min(nearest, length(p - testing::closestPointOnTriangle(p, corner(t, 0), corner(t, 1), corner(t, 2))));
      }
      worst = std::max(worst, nearest);
    }
  }
  return worst;
}

// The tile's shape sampled on a (kCurvatureSamples + 1)² grid of its interior.
std::vector<LocalShape> sampleShape(const BezierNet& net, const NodeSquare& leaf, const Tile& tile) {
  const double s = tile.size(), ls = leaf.size();
  const double x0 = (double(tile.ix) * s - double(leaf.ix) * ls) / ls, y0 = (double(tile.iy) * s - double(leaf.iy) * ls) / ls;
  const double k = s / ls, h = 1e-4;  // tile within the leaf's [0, 1]², and a difference step in it
  const auto d = [&](double a, double b) { return evaluateBezier(net.data(), x0 + k * a, y0 + k * b); };
  std::vector<LocalShape> shape;
  for (int j = 0; j <= kCurvatureSamples; ++j) {
    for (int i = 0; i <= kCurvatureSamples; ++i) {
      const double a = 0.02 + 0.96 * i / kCurvatureSamples, b = 0.02 + 0.96 * j / kCurvatureSamples;
      const PatchSample p = d(a, b), pu = d(a + h, b), mu = d(a - h, b), pv = d(a, b + h), mv = d(a, b - h);
      // Tile units: derivatives in (a, b) are k times those in the leaf's (s, t).
      const double scale = k * k / (2 * h);
      LocalShape x{p.dPds * k, p.dPdt * k, (pu.dPds - mu.dPds) * scale, (pv.dPds - mv.dPds) * scale,
                   (pv.dPdt - mv.dPdt) * scale, cross(p.dPds, p.dPdt)};
      x.normal = x.normal * (1 / length(x.normal));
      shape.push_back(x);
    }
  }
  return shape;
}

double form(double uu, double uv, double vv, const Tile& tile) {
  const double w = 1.0 / tile.ru, h = 1.0 / tile.rv;
  return (w * w * uu + 2 * w * h * uv + h * h * vv) / 8;
}

// §2's form with |n · f_uu|, |n · f_uv|, |n · f_vv| (n the unit normal at each sample).
double normalForm(const std::vector<LocalShape>& shape, const Tile& tile) {
  double uu = 0, uv = 0, vv = 0;
  for (const LocalShape& x : shape) {
    uu = std::max(uu, std::abs(dot(x.normal, x.fuu)));
    uv = std::max(uv, std::abs(dot(x.normal, x.fuv)));
    vv = std::max(vv, std::abs(dot(x.normal, x.fvv)));
  }
  return form(uu, uv, vv, tile);
}

// §8's route: inside, the normal part against one direction N plus the tilt |n − N| times §2;
// on the edges of a cell (two sides, two diagonals), the edge curve's deviation across its chord.
double routeEstimate(const std::vector<LocalShape>& shape, const Tile& tile) {
  const Vec3d axis = shape[shape.size() / 2].normal;
  double nuu = 0, nuv = 0, nvv = 0, uu = 0, uv = 0, vv = 0, tilt = 0, edges = 0;
  const double w = 1.0 / tile.ru, h = 1.0 / tile.rv;
  for (const LocalShape& x : shape) {
    nuu = std::max(nuu, std::abs(dot(axis, x.fuu)));
    nuv = std::max(nuv, std::abs(dot(axis, x.fuv)));
    nvv = std::max(nvv, std::abs(dot(axis, x.fvv)));
    uu = std::max(uu, length(x.fuu)), uv = std::max(uv, length(x.fuv)), vv = std::max(vv, length(x.fvv));
    tilt = std::max(tilt, length(x.normal - axis));
    const double du[4] = {w, 0, w, w}, dv[4] = {0, h, h, -h};
    for (int e = 0; e < 4; ++e) {
      const Vec3d chord = x.fu * du[e] + x.fv * dv[e];
      const Vec3d second = x.fuu * (du[e] * du[e]) + x.fuv * (2 * du[e] * dv[e]) + x.fvv * (dv[e] * dv[e]);
      edges = std::max(edges, length(across(second, chord * (1 / length(chord)))) / 8);
    }
  }
  return std::max(form(nuu, nuv, nvv, tile) + tilt * form(uu, uv, vv, tile), edges);
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(q * double(v.size())))];
}

int run(const char* path, double relative) {
  const ControlMesh mesh = readObjFile(path);
  const PatchSet patches = buildPatchSet(mesh);
  TessellationOptions options;
  options.tolerance = relative;
  options.relativeTolerance = true;
  const AdaptiveLayout layout = layoutAdaptive(patches, *patches.adaptive, options);
  const TriangleMesh output = tessellateAdaptive(patches, *patches.adaptive, layout);
  const SurfaceTree& tree = patches.adaptive->tree;
  std::vector<std::vector<uint32_t>> rootTriangles(tree.roots.size());
  for (uint32_t t = 0; t < output.triangleCount(); ++t) {
    const uint32_t tile = output.trianglePiece[t];
    const size_t root = size_t(std::upper_bound(layout.plan.rootFirstTile.begin(), layout.plan.rootFirstTile.end(), tile) -
                               layout.plan.rootFirstTile.begin()) - 1;
    rootTriangles[root].push_back(t);
  }
  SurfaceEvaluator evaluator(tree, patches);
  std::vector<TileFigures> figures;
  long triangles = 0;
  for (size_t r = 0; r + 1 < layout.plan.rootFirstTile.size(); ++r) {
    const NodeSquare root{tree.roots[r].node, 0, 0, 0};
    for (uint32_t t = layout.plan.rootFirstTile[r]; t < layout.plan.rootFirstTile[r + 1]; ++t) {
      const Tile& tile = layout.plan.tiles[t];
      const SurfaceNode& node = tree.nodes[tile.node.node];
      if (tile.ru * tile.rv < 2 || tile.cellwise || !node.isLeaf() || node.evCorners != 0) continue;
      const double measured = measuredDistance(evaluator, output, rootTriangles[r], root, tile);
      if (!(measured > 0)) continue;
      const std::vector<LocalShape> shape = sampleShape(pieceNet(tree, patches, tile.node.node), tile.node, tile);
      figures.push_back({tile.bound, measured, normalForm(shape, tile), routeEstimate(shape, tile)});
      triangles += 2L * tile.ru * tile.rv;
    }
  }
  if (figures.empty()) {
    std::printf("no grid tiles\n");
    return 0;
  }
  std::vector<double> bound, normal, route;
  for (const TileFigures& f : figures) {
    bound.push_back(f.bound / f.measured);
    normal.push_back(f.normalForm / f.measured);
    route.push_back(f.route / f.measured);
  }
  std::printf("%s at %g: %zu grid tiles, %ld of %zu triangles before stitching\n", path, relative, figures.size(),
              triangles, size_t(layout.plan.gridTriangles));
  std::printf("  bound / measured:              10%% %.2f  50%% %.2f  90%% %.2f\n", quantile(bound, 0.1),
              quantile(bound, 0.5), quantile(bound, 0.9));
  std::printf("  normal-only FMM86 / measured:  10%% %.2f  50%% %.2f  90%% %.2f\n", quantile(normal, 0.1),
              quantile(normal, 0.5), quantile(normal, 0.9));
  std::printf("  route estimate / measured:     10%% %.2f  50%% %.2f  90%% %.2f\n", quantile(route, 0.1),
              quantile(route, 0.5), quantile(route, 0.9));
  return 0;
}

}  // namespace
}  // namespace tessera

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s MODEL.obj RELATIVE_EPS\n", argv[0]);
    return 2;
  }
  return tessera::run(argv[1], std::atof(argv[2]));
}
