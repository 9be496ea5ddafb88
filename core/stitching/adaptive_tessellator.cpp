#include "core/stitching/adaptive_tessellator.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>

#include "core/adaptive/plan_scratch.h"
#include "core/base/error.h"
#include "core/base/parallel_chunks.h"
#include "core/base/work_checkpoint.h"
#include "core/stitching/face_triangles.h"
#include "core/stitching/tile_stitching.h"
#include "core/stitching/tile_triangulation.h"

namespace tessera {

namespace {

// Vertices evaluated, or grid cells triangulated, between checkpoints on a thread: a few
// milliseconds, however they fall into roots (one root at a fine tolerance can hold millions).
constexpr size_t kPointsPerCheckpoint = size_t(1) << 14;

// Where vertices [first, last) lie (face, sub-face, (u, v)): tests and tools read it, a GLB does
// not.
void recordRange(const AdaptiveSurface& surface, const Stitching& stitching, const std::vector<uint32_t>& tileRoot,
                 size_t first, size_t last, TriangleMesh& mesh) {
  for (size_t i = first; i < last; ++i) {
    const VertexRequest& request = stitching.vertices[i];
    const SurfaceRoot& root = surface.tree.roots[tileRoot[request.tile]];
    mesh.vertexFace[i] = root.baseFace;
    mesh.vertexSubFace[i] = root.subFace;
    mesh.vertexUv[2 * i] = request.u, mesh.vertexUv[2 * i + 1] = request.v;
  }
}

// Vertices [first, last) on the limit surface (and where each lies when `record`).
void evaluateRange(SurfaceEvaluator& evaluator, const AdaptiveSurface& surface, const AdaptivePlan& plan,
                   const Stitching& stitching, const std::vector<uint32_t>& tileRoot, bool record, size_t first,
                   size_t last, TriangleMesh& mesh, WorkCheckpoint& work) {
  for (size_t i = first; i < last; ++i) {
    work.done();
    const VertexRequest& request = stitching.vertices[i];
    const SurfaceSample sample = evaluator.evaluate(plan.tiles[request.tile].node, request.u, request.v);
    mesh.positions[i] = Vec3(sample.position);
    mesh.normals[i] = Vec3(sample.normal);
  }
  if (record) recordRange(surface, stitching, tileRoot, first, last, mesh);
}

// The runs' triangles one after the other into mesh.indices (and each triangle's tile into
// mesh.trianglePiece when `record`); returns the runs' away corners (TileTriangleOutput) as
// positions there. On all cores for large outputs: appended on one thread, the copy was 40 % of
// triangulation on bigguy at 1e-4 and kept it from scaling on 16 cores.
std::vector<uint32_t> concatenateRuns(const std::vector<TileTriangleOutput>& outputs,
                                      const std::vector<std::vector<uint32_t>>& tiles, bool record, TriangleMesh& mesh) {
  const size_t runs = outputs.size();
  std::vector<size_t> first(runs + 1, 0);  // run r's indices start at first[r]
  std::vector<uint32_t> away;
  for (size_t r = 0; r < runs; ++r) {
    first[r + 1] = first[r] + outputs[r].indices.size();
    for (uint32_t corner : outputs[r].awayCorners) away.push_back(uint32_t(first[r]) + corner);
  }
  mesh.indices.resize(first[runs]);
  if (record) mesh.trianglePiece.resize(first[runs] / 3);
  auto copyRun = [&](size_t r) {
    std::copy(outputs[r].indices.begin(), outputs[r].indices.end(), mesh.indices.begin() + ptrdiff_t(first[r]));
    if (record) std::copy(tiles[r].begin(), tiles[r].end(), mesh.trianglePiece.begin() + ptrdiff_t(first[r] / 3));
  };
  // A few hundred kilobytes are copied in less time than a parallel region costs.
  constexpr size_t kParallelCopy = size_t(1) << 16;
  if (first[runs] < kParallelCopy) {
    for (size_t r = 0; r < runs; ++r) copyRun(r);
  } else {
    tbb::parallel_for(size_t(0), runs, copyRun);
  }
  return away;
}

// Every vertex on the limit surface and every tile's triangles, on all cores. First the seam
// vertices, which tiles of several roots share (the copies that carry another side's normal then
// take their original's position bit for bit); then, run by run of roots, each root's own
// vertices and at once its tiles' triangles, so that a root's vertices are triangulated by the
// core that evaluated them, from its cache (the two were separate passes over all vertices and
// all tiles); then the runs concatenated in order. Where an `external` evaluation evaluates every
// vertex first, the runs only triangulate. Returns the corners facing against their
// vertex normals (TileTriangleOutput), as positions in mesh.indices.
std::vector<uint32_t> evaluateAndTriangulate(const PatchSet& patches, const AdaptiveSurface& surface,
                                             const AdaptivePlan& plan, const Stitching& stitching,
                                             const std::vector<uint32_t>& tileRoot, bool record, TriangleMesh& mesh,
                                             VertexEvaluation* external, const std::function<void()>& checkpoint) {
  const size_t count = stitching.vertices.size();
  mesh.positions.resize(count);
  mesh.normals.resize(count);
  if (record) {
    mesh.vertexFace.resize(count);
    mesh.vertexSubFace.resize(count);
    mesh.vertexUv.resize(2 * count);
    mesh.vertexPoint.resize(count);
    for (size_t i = 0; i < count; ++i) mesh.vertexPoint[i] = stitching.vertices[i].positionOf;
  }
  if (checkpoint) checkpoint();  // after the output's arrays are in place (a fraction of a second at 20M triangles)
  // Built per thread from references (the arguments form would copy the tree).
  tbb::enumerable_thread_specific<SurfaceEvaluator> evaluators([&] { return SurfaceEvaluator(surface.tree, patches); });
  const bool evaluated = external && external->evaluate(plan, stitching, mesh.positions, mesh.normals);
  // Runs are the parts that planned and stitched their roots (parallel_chunks.h).
  const size_t roots = plan.rootFirstTile.size() - 1;
  const size_t runs = ownedParts(roots, 16);
  std::vector<TileTriangleOutput> outputs(runs);
  std::vector<std::vector<uint32_t>> tiles(runs);
  const TriangulationVertices vertices{mesh.positions, mesh.normals};
  auto triangulateRun = [&](size_t r, size_t firstRoot, size_t endRoot) {
    if (checkpoint) checkpoint();
    WorkCheckpoint work(checkpoint, kPointsPerCheckpoint);
    if (!evaluated) {
      evaluateRange(evaluators.local(), surface, plan, stitching, tileRoot, record,
                    stitching.rootFirstVertex[firstRoot], stitching.rootFirstVertex[endRoot], mesh, work);
    }
    const size_t firstTile = plan.rootFirstTile[firstRoot], endTile = plan.rootFirstTile[endRoot];
    // Room for the run's triangles up front (a tile makes two a cell and one a side point past
    // its own, about), not grown by doubling from nothing.
    size_t room = 0;
    for (size_t t = firstTile; t < endTile; ++t) {
      room += 2 * size_t(plan.tiles[t].ru) * size_t(plan.tiles[t].rv) + stitching.sideFirst[4 * t + 4] - stitching.sideFirst[4 * t];
    }
    outputs[r].indices.reserve(3 * room);
    for (size_t t = firstTile; t < endTile; ++t) {
      work.done(1 + size_t(plan.tiles[t].ru) * size_t(plan.tiles[t].rv));
      const size_t before = outputs[r].indices.size();
      triangulateTile(stitching, t, plan.tiles[t], stitching.gridFirst[t], vertices, outputs[r]);
      if (record) tiles[r].insert(tiles[r].end(), (outputs[r].indices.size() - before) / 3, uint32_t(t));
    }
  };
  if (evaluated) {
    if (record) recordRange(surface, stitching, tileRoot, 0, count, mesh);
    for (size_t i = stitching.copyFirst; i < count; ++i) mesh.positions[i] = mesh.positions[stitching.vertices[i].positionOf];
    forOwnedParts(roots, 16, triangulateRun);
    return concatenateRuns(outputs, tiles, record, mesh);
  }
  // The seam vertices, each part an even share, before any run triangulates (in one parallel
  // region: parallel_chunks.h). A copy takes its original's position by evaluating the original's
  // point again (the same call, so the same bits), not from the original, which another part may
  // not have reached yet.
  const size_t seamFirst = stitching.rootFirstVertex.back(), copyFirst = stitching.copyFirst;
  auto share = [runs](size_t first, size_t end, size_t p) {
    return std::pair(first + p * (end - first) / runs, first + (p + 1) * (end - first) / runs);
  };
  auto evaluateSeams = [&](size_t p, size_t, size_t) {
    if (checkpoint) checkpoint();
    WorkCheckpoint work(checkpoint, kPointsPerCheckpoint);
    SurfaceEvaluator& evaluator = evaluators.local();
    const auto [seamsFrom, seamsTo] = share(seamFirst, copyFirst, p);
    const auto [copiesFrom, copiesTo] = share(copyFirst, count, p);
    evaluateRange(evaluator, surface, plan, stitching, tileRoot, record, seamsFrom, seamsTo, mesh, work);
    evaluateRange(evaluator, surface, plan, stitching, tileRoot, record, copiesFrom, copiesTo, mesh, work);
    for (size_t i = copiesFrom; i < copiesTo; ++i) {
      work.done();
      const VertexRequest& original = stitching.vertices[stitching.vertices[i].positionOf];
      mesh.positions[i] = Vec3(evaluator.evaluate(plan.tiles[original.tile].node, original.u, original.v).position);
    }
  };
  forOwnedPartsTwice(roots, 16, evaluateSeams, triangulateRun);
  return concatenateRuns(outputs, tiles, record, mesh);
}

// A face triangle's corners (core/stitching/face_triangles.h) in sub-face 0's coordinates unfolded past its
// spokes: the face's corners at (0, 0), (2, 0), (0, 2), the middles of its edges at (1, 0),
// (2, 1) (sub-face 1's (1, 0)) and (0, 1).
void faceTriangleParameters(const Stitching& stitching, size_t t, const uint32_t* corners, double* st) {
  static constexpr double kCorner[3][2] = {{0, 0}, {2, 0}, {0, 2}}, kMiddle[3][2] = {{1, 0}, {2, 1}, {0, 1}};
  const FaceTrianglePoints face = faceTrianglePoints(stitching, t);
  for (int c = 0; c < 3; ++c) {
    for (int k = 0; k < 3; ++k) {
      const double* at = face.corner[k] == corners[c] ? kCorner[k] : face.middle[k] == corners[c] ? kMiddle[k] : nullptr;
      if (at) st[2 * c] = at[0], st[2 * c + 1] = at[1];
    }
  }
}

// Triangle t's root and its corners' (u, v) there: a corner is the tile's inner grid point or
// one of its sides' points (before fold copies are made).
void recordParametersOf(size_t t, const AdaptiveSurface& surface, const AdaptivePlan& plan, const Stitching& stitching,
                        const std::vector<uint32_t>& tileRoot, TriangleMesh& mesh) {
  const uint32_t tileIndex = mesh.trianglePiece[t];
  const Tile& tile = plan.tiles[tileIndex];
  const SurfaceRoot& root = surface.tree.roots[tileRoot[tileIndex]];
  mesh.triangleFace[t] = root.baseFace, mesh.triangleSubFace[t] = root.subFace;
  if (tile.faceTriangle) return faceTriangleParameters(stitching, tileIndex, &mesh.indices[3 * t], &mesh.triangleST[6 * t]);
  const uint32_t gridFirst = stitching.gridFirst[tileIndex];
  const uint32_t gridCount = uint32_t((tile.ru - 1) * (tile.rv - 1));
  for (int k = 0; k < 3; ++k) {
    const uint32_t v = mesh.indices[3 * t + k];
    double x = -1, y = -1;
    if (v >= gridFirst && v < gridFirst + gridCount) {
      const uint32_t g = v - gridFirst;
      x = double(g % (tile.ru - 1) + 1) / tile.ru, y = double(g / (tile.ru - 1) + 1) / tile.rv;
    }
    for (int side = 0; side < 4 && x < 0; ++side) {
      size_t count;
      const SidePoint* points = stitching.side(tileIndex, side, count);
      for (size_t p = 0; p < count; ++p) {
        if (points[p].vertex != v) continue;
        const double at = points[p].at;
        x = side == 0 || side == 2 ? at : (side == 1 ? 1 : 0);
        y = side == 1 || side == 3 ? at : (side == 2 ? 1 : 0);
        break;
      }
    }
    mesh.triangleST[6 * t + 2 * k] = (double(tile.indexAlong(0)) + x) * tile.width();
    mesh.triangleST[6 * t + 2 * k + 1] = (double(tile.indexAlong(1)) + y) * tile.height();
  }
}

// Every triangle's, in chunks of 64K that each reach the checkpoint first (millions of triangles
// are seconds of work that a cancelled request must not finish).
void recordTriangleParameters(const AdaptiveSurface& surface, const AdaptivePlan& plan, const Stitching& stitching,
                              const std::vector<uint32_t>& tileRoot, TriangleMesh& mesh,
                              const std::function<void()>& checkpoint) {
  const size_t triangles = mesh.triangleCount();
  mesh.triangleST.resize(6 * triangles);
  mesh.triangleFace.resize(triangles);
  mesh.triangleSubFace.resize(triangles);
  constexpr size_t kChunk = size_t(1) << 16;
  tbb::parallel_for(size_t(0), (triangles + kChunk - 1) / kChunk, [&](size_t chunk) {
    if (checkpoint) checkpoint();
    for (size_t t = chunk * kChunk; t < std::min(triangles, (chunk + 1) * kChunk); ++t) {
      recordParametersOf(t, surface, plan, stitching, tileRoot, mesh);
    }
  });
}

// A fold narrower than the tiles there (the surface turns back within less than ε resolves)
// shows as triangles facing against a vertex's limit normal (`flagged`: those corners, as
// positions in mesh.indices, found by evaluateAndTriangulate). At this tolerance the fold is a
// crease: those triangles share a copy of the vertex (same position) whose normal is the
// average of their face normals, or each its own where no average faces all of them.
void splitFoldNormals(std::vector<uint32_t> flagged, TriangleMesh& mesh) {
  if (flagged.empty()) return;
  std::sort(flagged.begin(), flagged.end(), [&mesh](uint32_t a, uint32_t b) {
    return mesh.indices[a] < mesh.indices[b] || (mesh.indices[a] == mesh.indices[b] && a < b);
  });
  auto faceNormal = [&mesh](uint32_t corner) {
    const uint32_t* i = &mesh.indices[corner - corner % 3];
    return Vec3d(cross(mesh.positions[i[1]] - mesh.positions[i[0]], mesh.positions[i[2]] - mesh.positions[i[0]]));
  };
  const bool record = !mesh.vertexPoint.empty();
  auto copyVertex = [&mesh, record](uint32_t v, const Vec3d& normal) {
    mesh.positions.push_back(mesh.positions[v]);
    mesh.normals.push_back(Vec3(normal * (1 / length(normal))));
    if (record) {
      mesh.vertexFace.push_back(mesh.vertexFace[v]);
      mesh.vertexSubFace.push_back(mesh.vertexSubFace[v]);
      mesh.vertexUv.insert(mesh.vertexUv.end(), {mesh.vertexUv[2 * v], mesh.vertexUv[2 * v + 1]});
      mesh.vertexPoint.push_back(mesh.vertexPoint[v]);
    }
    return uint32_t(mesh.positions.size() - 1);
  };
  for (size_t first = 0; first < flagged.size();) {
    const uint32_t v = mesh.indices[flagged[first]];
    size_t end = first;
    Vec3d sum;
    while (end < flagged.size() && mesh.indices[flagged[end]] == v) sum += faceNormal(flagged[end++]);
    bool shared = length(sum) > 0;
    for (size_t k = first; k < end && shared; ++k) shared = dot(sum, faceNormal(flagged[k])) > 0;
    const uint32_t copy = shared ? copyVertex(v, sum) : 0;
    for (size_t k = first; k < end; ++k) {
      const Vec3d own = faceNormal(flagged[k]);
      mesh.indices[flagged[k]] = shared ? copy : (length(own) > 0 ? copyVertex(v, own) : v);
    }
    first = end;
  }
}

// Checks the pending tiles of `roots` against their neighbours; returns the squares of those
// whose bound breaks their ε. A root's check is a fraction of a microsecond, so roots go in
// chunks of 64: a small request checks on one thread (a parallel region costs more than its
// whole check), a large one on all.
std::vector<TileSquare> checkPending(const RootTiles& tiles, const TileNeighbors& neighbors,
                                     const std::vector<uint32_t>& roots) {
  constexpr size_t kChunk = 64;
  std::vector<std::vector<TileSquare>> failed((roots.size() + kChunk - 1) / kChunk);
  tbb::parallel_for(size_t(0), failed.size(), [&](size_t chunk) {
    for (size_t i = chunk * kChunk; i < std::min(roots.size(), (chunk + 1) * kChunk); ++i) {
      const uint32_t r = roots[i];
      for (uint32_t t = 0; t < tiles[r].size(); ++t) {
        const Tile& tile = tiles[r][t];
        if (!tile.pendingPair) continue;
        // Sides inside the root were checked while planning (Planner::settleInnerSides): only
        // those on base edges and spokes are asked about.
        uint8_t sides = tile.innerSidesWithPoints, onRoot = 0;
        for (int k = 0; k < 4; ++k) {
          if (!tile.onRootSide(k)) continue;
          onRoot |= uint8_t(1 << k);
          sides |= uint8_t(neighbors.sideGetsPoints(r, t, k) << k);
        }
        if (onRoot == 0) continue;  // it passed already
        if (tile.boundWithPoints(sides) > tile.tolerance) {
          failed[chunk].push_back({r, tile.level, tile.ix, tile.iy, sides});
        }
      }
    }
  });
  std::vector<TileSquare> all;
  for (const auto& list : failed) all.insert(all.end(), list.begin(), list.end());
  return all;
}

// The roots whose tiles can see a change in these: themselves and those across their sides
// (marked, then listed in order: no sort of the many repeats).
std::vector<uint32_t> affectedRoots(const RootSeams& seams, const std::vector<TileSquare>& changed, size_t rootCount) {
  std::vector<uint8_t> marked(rootCount, 0);
  for (const TileSquare& q : changed) {
    marked[q.root] = 1;
    for (int k = 0; k < 4; ++k) {
      for (uint32_t i = seams.first[4 * size_t(q.root) + k]; i < seams.first[4 * size_t(q.root) + k + 1]; ++i) {
        marked[seams.spans[i].root] = 1;
      }
    }
  }
  std::vector<uint32_t> roots;
  for (uint32_t r = 0; r < rootCount; ++r) {
    if (marked[r]) roots.push_back(r);
  }
  return roots;
}

// Settles every pending tile's bound from its sides as stitched; false if one breaks its ε (the
// prediction missed a point: not expected, but then planning goes on conservatively there).
bool settlePending(AdaptivePlan& plan, const Stitching& stitching, std::vector<TileSquare>& failed) {
  plan.guaranteedBound = 0;
  size_t root = 0;
  for (size_t t = 0; t < plan.tiles.size(); ++t) {
    Tile& tile = plan.tiles[t];
    while (plan.rootFirstTile[root + 1] <= t) ++root;
    if (tile.pendingPair) {
      uint8_t sides = 0;
      for (int k = 0; k < 4; ++k) {
        // Points beside the side's own grid points (its corners, for a one-cell tile).
        size_t count;
        stitching.side(t, k, count);
        sides |= uint8_t((count > size_t(k == 0 || k == 2 ? tile.ru : tile.rv) + 1) << k);
      }
      const float bound = tile.boundWithPoints(sides);
      if (bound > tile.tolerance) failed.push_back({uint32_t(root), tile.level, tile.ix, tile.iy, sides});
      tile.bound = bound;
      tile.pendingPair = false;
    }
    plan.guaranteedBound = std::max(plan.guaranteedBound, double(tile.bound));
  }
  return failed.empty();
}

}  // namespace

// Rounds of planning: one-cell tiles planned on their corners' bound alone are checked against
// their neighbours (tile_neighbors.h) and planned again without that shortcut where they fail,
// which can change what their neighbours see, until none fails; then triangular faces are joined
// where they can be (face_triangles.h) and the seams are stitched.
AdaptiveLayout layoutAdaptive(const PatchSet& patches, const AdaptiveSurface& surface,
                              const TessellationOptions& options) {
  AdaptiveLayout layout;
  std::vector<uint32_t> roots(surface.tree.roots.size());
  std::iota(roots.begin(), roots.end(), 0u);
  const PlanScratchLease scratch;
  RootTiles& tiles = scratch->tiles;
  // Each root's tiles indexed for the rounds by the core that planned it.
  planRoots(surface.tree, patches, options, tiles, &scratch->indexes);
  TileNeighbors neighbors(surface.rootSeams, tiles, scratch->indexes);
  FaceTriangles faceTriangles(surface.tree.faceFirstRoot.size());
  for (std::vector<uint32_t> check = roots;;) {
    while (!check.empty()) {
      ++layout.rounds;
      const std::vector<TileSquare> failed = checkPending(tiles, neighbors, check);
      if (failed.empty()) break;
      // A failed square is planned with no pending tiles (a merged tile's with its quadrants
      // unmerged, which can fail once more), so the rounds end.
      replanSquares(surface.tree, patches, options, failed, tiles, &neighbors.roots());
      check = affectedRoots(surface.rootSeams, failed, surface.tree.roots.size());
    }
    layout.plan = flattenPlan(tiles);
    if (layout.plan.gridTriangles > options.maxTriangles) {
      throwLimit("the request would produce about " + std::to_string(layout.plan.gridTriangles) +
                 " triangles, over the budget of " + std::to_string(options.maxTriangles) +
                 "; raise the tolerance or the triangle budget");
    }
    if (options.beforeOutput) options.beforeOutput(layout.plan.gridTriangles);
    faceTriangles.join(layout.plan, patches, surface);
    layout.stitching = stitchTiles(layout.plan, surface.tree, surface.lines, options.checkpoint);
    // A face triangle refused here is its sub-faces' tiles again next time, as `tiles` has them.
    const bool joined = faceTriangles.hold(layout.plan, layout.stitching, surface.tree);
    std::vector<TileSquare> failed;
    const bool settled = settlePending(layout.plan, layout.stitching, failed);
    if (joined && settled) return layout;
    check.clear();
    if (settled) continue;
    // The failed squares planned again; the other pending tiles stay pending in `tiles` and are
    // checked again with their new neighbours.
    replanSquares(surface.tree, patches, options, failed, tiles, &neighbors.roots());
    check = roots;
  }
}

TriangleMesh tessellateAdaptive(const PatchSet& patches, const AdaptiveSurface& surface, const AdaptiveLayout& layout,
                                bool recordParameters, const std::function<void()>& checkpoint,
                                VertexEvaluation* evaluation) {
  const AdaptivePlan& plan = layout.plan;
  const Stitching& stitching = layout.stitching;
  std::vector<uint32_t> tileRoot(plan.tiles.size());
  for (size_t r = 0; r + 1 < plan.rootFirstTile.size(); ++r) {
    std::fill(tileRoot.begin() + plan.rootFirstTile[r], tileRoot.begin() + plan.rootFirstTile[r + 1], uint32_t(r));
  }
  TriangleMesh mesh;
  std::vector<uint32_t> away =
      evaluateAndTriangulate(patches, surface, plan, stitching, tileRoot, recordParameters, mesh, evaluation, checkpoint);
  if (checkpoint) checkpoint();
  if (recordParameters) recordTriangleParameters(surface, plan, stitching, tileRoot, mesh, checkpoint);
  splitFoldNormals(std::move(away), mesh);
  return mesh;
}

}  // namespace tessera
