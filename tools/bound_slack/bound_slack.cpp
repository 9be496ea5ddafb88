// tessera-bound-slack: how far the planner's proven bounds sit above the measured distance, and
// where the slack lies, for the grid tiles of an adaptive tessellation (docs/ADAPTIVE.md §8). A
// grid tile here is a tile of at least two cells (not cell-wise) without an extraordinary vertex.
// For each, against the distance of the surface over it from the output triangles of its root
// (7 × 7 samples a cell, each to its nearest such triangle: one side of the two-sided distance
// the bound covers; other roots are left out so that the far side of a thin wall does not count):
//  - its bound;
//  - the equal-parameter distance sup ‖f − L‖ over its cells, L the two triangles of each cell
//    along the better of the two diagonals (sampled): what any bound at equal parameters must
//    cover, so bound / this is the slack of the bound's form and this / measured the share of
//    the parameterization's in-plane distortion;
//  - §2's FMM86 form with the second derivatives' sup sampled instead of hull bounds (the hull's
//    share of the slack);
//  - for tiles inside one piece, §2a's bound (core/bounds/edge_curvature.h) at the tile's rates over §2's
//    (both from the piece's net: the share §2a takes off, or adds);
//  - §2's form with only the components of the second derivatives along the surface normal
//    (sampled, pointwise; an estimate of what a geometric bound could reach, not a bound);
//  - a directional form (sampled, an estimate, not a bound): for a triangle in a w × h box with
//    one edge along u or v, the variance identity Σ λ_k q(x_k) − q(x) = Σ_{j<k} λ_j λ_k q(x_j − x_k)
//    for the quadratic q = ½ D²f gives ½ max_λ Σ_{j<k} λ_j λ_k |D²f[e_jk, e_jk]|, with
//    |D²f[e, e]| bounded by w²|f_uu| or h²|f_vv| on the axis edge and on the others by the sup
//    over every direction the box holds.
//
//   build/tools/tessera-bound-slack ../shared/models/bigguy.obj 1e-3
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "core/bounds/edge_curvature.h"
#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "core/stitching/adaptive_tessellator.h"
#include "core/surface/adaptive_surface.h"
#include "core/surface/surface_evaluation.h"
#include "reference/triangle_bvh.h"  // closestPointOnTriangle

namespace tessera {
namespace {

constexpr int kCellSamples = 6;     // intervals a cell side is sampled at
constexpr int kShapeSamples = 16;   // intervals a tile side is sampled at for second derivatives

struct TileFigures {
  double bound, measured, equalParameter, sampledForm, directionalForm;
  double normalForm = 0;  // §2's form with the normal components of f_uu, f_uv, f_vv only, pointwise
  double edgeOverCurvature = -1;  // §2a / §2 from the net, for tiles inside one piece
};

// §2a's bound over §2's at the tile's rates, from the net of the tile's square; -1 for a tile
// that is not inside one piece.
double edgeOverCurvature(const SurfaceTree& tree, const PatchSet& patches, const Tile& tile) {
  const SurfaceNode& node = tree.nodes[tile.node.node];
  if (node.kind != NodeKind::kRegularLeaf && node.kind != NodeKind::kFasLeaf) return -1;
  const BezierNet net = squareNet(tree, patches, tile.node, tile.level, tile.ix, tile.iy);
  return gridTileBound(edgeCurvature(net), tile.ru, tile.rv) /
         interpolationBound(netCurvature(net.data()), 1.0 / tile.ru, 1.0 / tile.rv);
}

// Where in its root a point of the tile at (a, b) ∈ [0, 1]² lies.
struct TileFrame {
  NodeSquare root;
  double u0, v0, w, h;
  TileFrame(const NodeSquare& r, const Tile& tile)
      : root(r),
        u0(double(tile.indexAlong(0)) * tile.width()),
        v0(double(tile.indexAlong(1)) * tile.height()),
        w(tile.width()),
        h(tile.height()) {}
  Vec3d at(SurfaceEvaluator& evaluator, double a, double b) const {
    return evaluator.evaluate(root, u0 + w * a, v0 + h * b).position;
  }
};

// The largest distance of the surface over the tile's cells from the given triangles.
double measuredDistance(SurfaceEvaluator& evaluator, const TriangleMesh& mesh, const std::vector<uint32_t>& triangles,
                        const TileFrame& frame, const Tile& tile) {
  const int nu = tile.ru * kCellSamples, nv = tile.rv * kCellSamples;
  const auto corner = [&](uint32_t t, int k) { return Vec3d(mesh.positions[mesh.indices[3 * t + uint32_t(k)]]); };
  double worst = 0;
  for (int j = 0; j <= nv; ++j) {
    for (int i = 0; i <= nu; ++i) {
      const Vec3d p = frame.at(evaluator, double(i) / nu, double(j) / nv);
      double nearest = INFINITY;
      for (const uint32_t t : triangles) {
        nearest = std::min(nearest, length(p - testing::closestPointOnTriangle(p, corner(t, 0), corner(t, 1), corner(t, 2))));
      }
      worst = std::max(worst, nearest);
    }
  }
  return worst;
}

// sup ‖f − L‖ over the cells, each split along diagonal 0 (corners 0–2) or 1 (corners 1–3).
double equalParameterDistance(SurfaceEvaluator& evaluator, const TileFrame& frame, const Tile& tile, int diagonal) {
  double worst = 0;
  for (int cj = 0; cj < tile.rv; ++cj) {
    for (int ci = 0; ci < tile.ru; ++ci) {
      const auto f = [&](double a, double b) { return frame.at(evaluator, (ci + a) / tile.ru, (cj + b) / tile.rv); };
      const Vec3d c00 = f(0, 0), c10 = f(1, 0), c01 = f(0, 1), c11 = f(1, 1);
      for (int j = 0; j <= kCellSamples; ++j) {
        for (int i = 0; i <= kCellSamples; ++i) {
          const double a = double(i) / kCellSamples, b = double(j) / kCellSamples;
          Vec3d l;
          if (diagonal == 0) {
            l = a >= b ? c00 + (c10 - c00) * a + (c11 - c10) * b : c00 + (c01 - c00) * b + (c11 - c01) * a;
          } else {
            l = a + b <= 1 ? c00 + (c10 - c00) * a + (c01 - c00) * b : c11 + (c01 - c11) * (1 - a) + (c10 - c11) * (1 - b);
          }
          worst = std::max(worst, length(f(a, b) - l));
        }
      }
    }
  }
  return worst;
}

// The FMM86 form and the directional form, both from second derivatives sampled by central
// differences (in cell units: w² f_uu, w h f_uv, h² f_vv) on a grid over the tile.
void sampledForms(SurfaceEvaluator& evaluator, const TileFrame& frame, const Tile& tile, double& fmm, double& directional,
                  double& normal) {
  double uu = 0, uv = 0, vv = 0, across = 0;
  normal = 0;
  const double d = 1e-3 / std::max(tile.ru, tile.rv);
  for (int j = 0; j <= kShapeSamples; ++j) {
    for (int i = 0; i <= kShapeSamples; ++i) {
      const double a = 0.01 + 0.98 * i / kShapeSamples, b = 0.01 + 0.98 * j / kShapeSamples;
      const auto f = [&](double x, double y) { return frame.at(evaluator, a + x * d, b + y * d); };
      const Vec3d p = f(0, 0);
      const double w = 1.0 / tile.ru, h = 1.0 / tile.rv;
      const Vec3d fuu = (f(1, 0) - p * 2 + f(-1, 0)) * (w * w / (d * d));
      const Vec3d fvv = (f(0, 1) - p * 2 + f(0, -1)) * (h * h / (d * d));
      const Vec3d fuv = (f(1, 1) - f(1, -1) - f(-1, 1) + f(-1, -1)) * (w * h / (4 * d * d));
      uu = std::max(uu, length(fuu)), uv = std::max(uv, length(fuv)), vv = std::max(vv, length(fvv));
      // The tangential parts move points along the surface; only the normal parts move it off.
      Vec3d n = cross(f(1, 0) - f(-1, 0), f(0, 1) - f(0, -1));
      n = n * (1 / length(n));
      normal = std::max(normal, (std::abs(dot(n, fuu)) + 2 * std::abs(dot(n, fuv)) + std::abs(dot(n, fvv))) / 8);
      // Every direction (δ, ±h), |δ| ≤ w, and (w, ±δ'), |δ'| ≤ h: the Bernstein coefficients of
      // the quadratic in δ on [0, w] and [−w, 0], and likewise in δ'.
      across = std::max({across, length(fuu + fuv * 2 + fvv), length(fuu - fuv * 2 + fvv), length(fvv + fuv),
                         length(fvv - fuv), length(fuu + fuv), length(fuu - fuv), length(fuu), length(fvv)});
    }
  }
  fmm = (uu + 2 * uv + vv) / 8;
  directional = simplexMax(std::max(uu, vv), across, across) / 2;
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(q * double(v.size())))];
}

int run(const char* path, double relative) {
  const ControlMesh mesh = readObjFile(path);
  const PatchSet patches = buildPatchSet(mesh);
  TessellationOptions options;
  options.accuracy = Accuracy::relative(relative);
  const AdaptiveLayout layout = layoutAdaptive(patches, *patches.adaptive, options);
  const TriangleMesh output = tessellateAdaptive(patches, *patches.adaptive, layout, true);
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
      // A rectangle's rates are over several squares: §2a's ratio below is per square.
      if (tile.ru * tile.rv < 2 || tile.cellwise || tile.spanU || tile.spanV) continue;
      if (tree.nodes[tile.node.node].evCorners != 0) continue;
      const TileFrame frame(root, tile);
      const double measured = measuredDistance(evaluator, output, rootTriangles[r], frame, tile);
      if (!(measured > 0)) continue;
      TileFigures f{tile.bound, measured, 0, 0, 0};
      f.equalParameter = std::min(equalParameterDistance(evaluator, frame, tile, 0),
                                  equalParameterDistance(evaluator, frame, tile, 1));
      sampledForms(evaluator, frame, tile, f.sampledForm, f.directionalForm, f.normalForm);
      if (tile.ru >= 2 && tile.rv >= 2) f.edgeOverCurvature = edgeOverCurvature(tree, patches, tile);
      figures.push_back(f);
      triangles += 2L * tile.ru * tile.rv;
    }
  }
  if (figures.empty()) {
    std::printf("no grid tiles\n");
    return 0;
  }
  std::printf("%s at %g: %zu grid tiles, %ld of %zu triangles before stitching\n", path, relative, figures.size(),
              triangles, size_t(layout.plan.gridTriangles));
  const auto row = [&figures](const char* name, auto ratio) {
    std::vector<double> v;
    for (const TileFigures& f : figures) v.push_back(ratio(f));
    std::printf("  %-44s 10%% %5.2f  50%% %5.2f  90%% %5.2f\n", name, quantile(v, 0.1), quantile(v, 0.5), quantile(v, 0.9));
  };
  row("bound / measured", [](const TileFigures& f) { return f.bound / f.measured; });
  row("equal-parameter distance / measured", [](const TileFigures& f) { return f.equalParameter / f.measured; });
  row("FMM86 form, sampled derivatives / measured", [](const TileFigures& f) { return f.sampledForm / f.measured; });
  row("directional form, sampled / measured", [](const TileFigures& f) { return f.directionalForm / f.measured; });
  row("FMM86 form, normal parts only, sampled / measured", [](const TileFigures& f) { return f.normalForm / f.measured; });
  std::vector<TileFigures> onePiece;
  for (const TileFigures& f : figures) {
    if (f.edgeOverCurvature > 0) onePiece.push_back(f);
  }
  if (!onePiece.empty()) {
    figures.swap(onePiece);
    row("sec. 2a / sec. 2 at the tile's rates, one piece", [](const TileFigures& f) { return f.edgeOverCurvature; });
  }
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
