#include "core/stitching/tile_stitching.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <memory>
#include <numeric>

#include "core/base/parallel_chunks.h"
#include "core/base/work_checkpoint.h"
#include "core/stitching/face_triangles.h"
#include "core/stitching/line_points.h"
#include "core/stitching/stitch_arena.h"

namespace tessera {

namespace {

using namespace line_points;

// Work between checkpoints on a thread, in tiles visited, tile sides placed on a line and points
// made: a few milliseconds, however it falls into roots (one root at a fine tolerance can hold
// tens of thousands of tiles and millions of points, seconds of work that a cancelled call must
// not finish).
constexpr size_t kWorkPerCheckpoint = size_t(1) << 14;
using namespace stitch;

// The corner (0..3, counter-clockwise from (ix, iy)) at which side k ends, low or high along it.
uint32_t sideEndCorner(int k, bool high) {
  static constexpr uint32_t kCorner[4][2] = {{0, 1}, {1, 2}, {3, 2}, {0, 3}};
  return kCorner[k][high];
}

// A side point that splits its vertex's normal (a qualifier ≥ 0): the claim of its tile's side on
// that vertex (splitNormals).
struct NormalClaim {
  uint32_t vertex;
  int qualifier;
  uint32_t tile, sidePoint;
  int side;
};

struct RootSlice {
  const Arena* arena = nullptr;  // null: a root without tiles (a hole)
  uint32_t localsFrom = 0, localsCount = 0;
  uint32_t usesFrom[5] = {0, 0, 0, 0, 0};  // root side k's boundary uses: [usesFrom[k], usesFrom[k + 1])
};

struct Slot {
  uint32_t offset = 0, count = 0;
};

// A tile side on a boundary line: its points in an arena's linePool, and the line.
struct LineSlot {
  const Arena* arena = nullptr;
  uint32_t offset = 0, count = 0, line = 0;
};

// A boundary line once resolved: its own points (not nodes) in an arena's ownPoints, where they
// go among the seam vertices, and for each node the vertex request of the lowest tile with a
// corner there.
struct LineRecord {
  const Arena* arena = nullptr;
  uint32_t ownFrom = 0, ownCount = 0, firstOwn = 0;
  VertexRequest claim[3] = {{UINT32_MAX, 0, 0, 0}, {UINT32_MAX, 0, 0, 0}, {UINT32_MAX, 0, 0, 0}};
};

// Side k of tile t on a line, before its position there is set.
LineUse sideUse(const Tile& tile, uint32_t t, int k) {
  LineUse use;
  const bool alongU = k == 0 || k == 2;
  use.cells = alongU ? tile.ru : tile.rv;
  use.exp = tile.levelAlong(k);
  use.kept = tile.keptIntervals(k);
  use.tile = t;
  use.side = uint8_t(k);
  return use;
}

// The point at `along` (0..1) of side k of a tile, in root coordinates.
void sidePoint(const Tile& tile, int k, double along, double& u, double& v) {
  const double x = double(tile.indexAlong(0)), y = double(tile.indexAlong(1));
  const bool alongU = k == 0 || k == 2;
  u = (alongU ? x + along : x + (k == 1)) * tile.width();
  v = (alongU ? y + (k == 2) : y + along) * tile.height();
}

// A tile's corner c (0..3, counter-clockwise from (ix, iy)) in root coordinates.
int64_t cornerX(const Tile& tile, uint32_t c) {
  return rootCoordinate(tile.level, c == 1 || c == 2 ? tile.ixEnd() : tile.ix);
}
int64_t cornerY(const Tile& tile, uint32_t c) {
  return rootCoordinate(tile.level, c >= 2 ? tile.iyEnd() : tile.iy);
}

// Tile t's side on its root's boundary through its corner (x, y), as side 4t + k, and which end.
uint32_t boundarySideEnd(const Tile& tile, uint32_t t, int64_t x, int64_t y, uint8_t& end) {
  int k;
  if (y == 0) {
    k = 0, end = x != cornerX(tile, 0);
  } else if (x == kRootScale) {
    k = 1, end = y != cornerY(tile, 0);
  } else if (y == kRootScale) {
    k = 2, end = x != cornerX(tile, 0);
  } else {
    k = 3, end = y != cornerY(tile, 0);
  }
  return 4 * t + uint32_t(k);
}

class Stitcher {
 public:
  Stitcher(const AdaptivePlan& plan, const SurfaceTree& tree, const SeamLines& lines,
           const std::function<void()>& checkpoint)
      : plan_(plan), tree_(tree), lines_(lines), checkpoint_(checkpoint) {}
  Stitcher(const Stitcher&) = delete;
  Stitcher& operator=(const Stitcher&) = delete;
  ~Stitcher() {
    for (SlotArena& arena : arenas_) arenaPool().give(std::move(arena.arena), arena.slot);
  }
  Stitching run();

 private:
  void stitchRoot(uint32_t root, Arena& a, WorkCheckpoint& work);
  void resolveInnerLine(uint32_t root, size_t from, size_t to, Arena& a);
  void gatherUses(const SeamLines::Line& line, std::vector<LineUse>& uses) const;
  void resolveBoundaryLine(uint32_t l, Arena& a);
  bool resolveUniformLine(uint32_t l, Arena& a);
  void writeBoundaryLine(uint32_t l, Arena& a);
  void numberSeamVertices();
  int boundaryQualifier(const LineUse& use, const SeamLines::Line& line, bool end, double along) const;
  VertexRequest pointOn(const LineUse& use, double along) const;
  uint32_t seamVertex(const PendingPoint& point, uint32_t line) const;
  void assembleRoot(uint32_t r);
  void assemble();
  void splitNormals();

  const AdaptivePlan& plan_;
  const SurfaceTree& tree_;
  const SeamLines& lines_;
  const std::function<void()>& checkpoint_;
  // Each thread's arena, from the pool, the one this slot gave back where it can (scratch_pool.h).
  struct SlotArena {
    std::unique_ptr<Arena> arena;
    int slot;
  };
  tbb::enumerable_thread_specific<SlotArena> arenas_{[] {
    const int slot = tbb::this_task_arena::current_thread_index();
    return SlotArena{arenaPool().take(slot), slot};
  }};
  std::vector<uint32_t> tileRoot_;
  std::vector<RootSlice> slices_;
  std::vector<Slot> innerSide_;      // per tile side 4t + k inside its root: its points in the arena's pool
  std::vector<uint32_t> gridLocal_;  // per tile: root-local id of its first grid vertex
  std::vector<LineRecord> records_;  // per line
  std::vector<LineSlot> boundarySide_;  // per tile side on its root's boundary
  std::vector<uint32_t> nodeVertex_;  // per node: its seam vertex
  std::vector<VertexRequest> nodeVertices_;  // the first seam vertices, nodes that have one
  uint32_t seamCount_ = 0;
  std::vector<uint32_t> localFirst_;  // per root, its first final vertex
  std::vector<std::vector<NormalClaim>> normalClaims_;  // per root, found while assembling
  uint32_t seamFirst_ = 0;
  Stitching out_;
};

// One root: its inner corners and the lines inside it are resolved here; its sides on base edges
// and spokes wait for the other roots there (resolveBoundaryLine).
void Stitcher::stitchRoot(uint32_t root, Arena& a, WorkCheckpoint& work) {
  const uint32_t first = plan_.rootFirstTile[root], last = plan_.rootFirstTile[root + 1];
  RootSlice& slice = slices_[root];
  slice.arena = &a;
  slice.localsFrom = uint32_t(a.locals.size());
  // Inner corners first, numbered in (x, y) order, each evaluated by the first tile with a corner
  // there; cornerId names them per tile corner 4 (t − first) + c (UINT32_MAX: not inner).
  a.inner.clear();
  a.cornerId.assign(4 * size_t(last - first), UINT32_MAX);
  for (uint32_t t = first; t < last; ++t) {
    work.done();
    const Tile& tile = plan_.tiles[t];
    for (uint32_t c = 0; c < 4; ++c) {
      const int64_t x = cornerX(tile, c), y = cornerY(tile, c);
      if (x > 0 && x < kRootScale && y > 0 && y < kRootScale) a.inner.push_back({x, y, 4 * (t - first) + c});
    }
  }
  std::sort(a.inner.begin(), a.inner.end());
  for (size_t i = 0; i < a.inner.size(); ++i) {
    const InnerCorner& corner = a.inner[i];
    if (i == 0 || corner.x != a.inner[i - 1].x || corner.y != a.inner[i - 1].y) {
      a.locals.push_back({first + corner.tileCorner / 4, double(corner.x) * exp2i(-kRootBits),
                          double(corner.y) * exp2i(-kRootBits), 0});
    }
    a.cornerId[corner.tileCorner] = uint32_t(a.locals.size() - 1) - slice.localsFrom;
  }
  // Sides on the root's boundary, root side by root side, placed on their line.
  for (int k = 0; k < 4; ++k) {
    slice.usesFrom[k] = uint32_t(a.boundaryUses.size());
    const SideLine& line = lines_.sideLine[4 * size_t(root) + k];
    const int d = line.halves == 2 ? 1 : 0;
    for (uint32_t t = first; t < last; ++t) {
      const Tile& tile = plan_.tiles[t];
      if (!tile.onRootSide(k)) continue;
      work.done();
      if (tile.faceTriangle) {
        // Its only side on a line: the other half of edge k − 1 is the previous sub-face's, the
        // spokes have none.
        if (k == 0) a.boundaryUses.push_back(faceEdgeUse(tile, t, line));
        continue;
      }
      LineUse use = sideUse(tile, t, k);
      const int level = tile.levelAlong(k);
      const uint64_t along = tile.indexAlong(k);
      use.a = (Int(line.origin) * use.cells << (level + d)) + line.sign * Int(along) * use.cells;
      use.sign = line.sign;
      use.exp = level + d;
      const int64_t origin = line.origin ? kLineScale : 0, scale = line.halves == 1 ? 2 : 1;
      use.t0 = origin + line.sign * scale * rootCoordinate(level, along);
      use.t1 = origin + line.sign * scale * rootCoordinate(level, along + 1);
      if (use.t1 < use.t0) std::swap(use.t0, use.t1);
      a.boundaryUses.push_back(use);
    }
  }
  slice.usesFrom[4] = uint32_t(a.boundaryUses.size());
  // Sides inside the root, on lines keyed (axis, fixed coordinate).
  a.innerUses.clear();
  a.innerKeys.clear();
  for (uint32_t t = first; t < last; ++t) {
    work.done();
    const Tile& tile = plan_.tiles[t];
    for (int k = 0; k < 4; ++k) {
      if (tile.onRootSide(k)) continue;
      LineUse use = sideUse(tile, t, k);
      use.a = Int(tile.indexAlong(k)) * use.cells;
      const int64_t fixed = k == 0   ? cornerY(tile, 0)
                            : k == 1 ? cornerX(tile, 1)
                            : k == 2 ? cornerY(tile, 2)
                                     : cornerX(tile, 0);
      const uint64_t axis = k == 0 || k == 2 ? 1 : 0;
      a.innerKeys.push_back({axis << 63 | uint64_t(fixed), uint32_t(a.innerUses.size())});
      a.innerUses.push_back(use);
    }
  }
  std::sort(a.innerKeys.begin(), a.innerKeys.end());
  for (size_t i = 0; i < a.innerKeys.size();) {
    size_t j = i;
    while (j < a.innerKeys.size() && a.innerKeys[j].line == a.innerKeys[i].line) ++j;
    resolveInnerLine(root, i, j, a);
    work.done((j - i) + a.points.points.size());
    i = j;
  }
  for (uint32_t t = first; t < last; ++t) {
    const Tile& tile = plan_.tiles[t];
    work.done(1 + size_t(tile.ru - 1) * size_t(tile.rv - 1));
    gridLocal_[t] = uint32_t(a.locals.size()) - slice.localsFrom;
    for (int j = 1; j < tile.rv; ++j) {
      for (int i = 1; i < tile.ru; ++i) {
        VertexRequest& request = a.locals.emplace_back(VertexRequest{t, 0, 0, 0});
        tile.gridPoint(i, j, request.u, request.v);
      }
    }
  }
  slice.localsCount = uint32_t(a.locals.size()) - slice.localsFrom;
}

// Inner keys [from, to) of the arena: one line inside the root.
void Stitcher::resolveInnerLine(uint32_t root, size_t from, size_t to, Arena& a) {
  const RootSlice& slice = slices_[root];
  const int axis = a.innerKeys[from].axis();
  const int64_t fixed = a.innerKeys[from].fixed();
  std::vector<LineUse>& line = a.line;
  line.clear();
  for (size_t i = from; i < to; ++i) line.push_back(a.innerUses[a.innerKeys[i].use]);
  LinePoints& points = a.points;
  resolveLine(line.data(), line.size(), points);
  // A point that ends a side is that side's tile corner (endOf: 2 · use + (1 at its high end)
  // + 1; 0 for none).
  a.endOf.assign(points.points.size(), 0);
  for (size_t u = 0; u < line.size(); ++u) {
    for (uint32_t high = 0; high < 2; ++high) {
      const Int end = high ? points.hi[u] : points.lo[u];
      a.endOf[std::lower_bound(points.points.begin(), points.points.end(), end) - points.points.begin()] =
          uint32_t(2 * u + high + 1);
    }
  }
  a.resolved.assign(points.points.size(), {0, Ref::kLocal, 0, -1, 0, 0});
  const std::vector<uint32_t>& order = byStart(points);
  size_t cursor = 0;
  for (size_t p = 0; p < points.points.size(); ++p) {
    const Int value = points.points[p];
    PendingPoint& point = a.resolved[p];
    if (a.endOf[p] != 0) {
      // The corner of the tile this side ends at (inner lines run with u or v).
      const LineUse& use = line[(a.endOf[p] - 1) / 2];
      const uint32_t t = use.tile;
      const Tile& tile = plan_.tiles[t];
      const bool high = (a.endOf[p] - 1) % 2;
      const uint32_t id = a.cornerId[4 * (t - plan_.rootFirstTile[root]) + sideEndCorner(use.side, high)];
      if (id != UINT32_MAX) {
        point.id = id;
      } else {
        const int64_t along = axis == 1 ? cornerX(tile, high) : cornerY(tile, 3 * high);
        const int64_t x = axis == 1 ? along : fixed, y = axis == 1 ? fixed : along;
        point.kind = Ref::kSideEnd;
        point.id = boundarySideEnd(plan_.tiles[t], t, x, y, point.end);
      }
      continue;
    }
    const size_t owner = holder(points, order, cursor, value);
    point.id = uint32_t(a.locals.size()) - slice.localsFrom;
    const double along = double(toLongDouble(value) / toLongDouble(points.denominator));
    const double across = double(fixed) * exp2i(-kRootBits);
    a.locals.push_back({line[owner].tile, axis == 1 ? along : across, axis == 1 ? across : along, 0});
  }
  for (size_t u = 0; u < line.size(); ++u) {
    const auto begin = std::lower_bound(points.points.begin(), points.points.end(), points.lo[u]) - points.points.begin();
    const auto end = std::upper_bound(points.points.begin(), points.points.end(), points.hi[u]) - points.points.begin();
    innerSide_[4 * size_t(line[u].tile) + line[u].side] = {uint32_t(a.pool.size()), uint32_t(end - begin)};
    for (auto p = begin; p < end; ++p) {
      PendingPoint point = a.resolved[p];
      sideCoordinates(line[u], points.lo[u], points.hi[u], points.cell[u], points.points[p], point.at, point.back);
      a.pool.push_back(point);
    }
  }
}

// A boundary line's tile sides, root side by root side (ascending), each root's in tile order.
void Stitcher::gatherUses(const SeamLines::Line& line, std::vector<LineUse>& uses) const {
  uses.clear();
  for (uint32_t i = line.firstSide; i < line.firstSide + line.sideCount; ++i) {
    const uint32_t side = lines_.rootSides[i];
    const RootSlice& slice = slices_[side / 4];
    if (slice.arena == nullptr) continue;
    const uint32_t k = side % 4;
    uses.insert(uses.end(), slice.arena->boundaryUses.begin() + slice.usesFrom[k],
                slice.arena->boundaryUses.begin() + slice.usesFrom[k + 1]);
  }
}

// Node j of a line sits at t = j/2: in the line's units, j · denominator / 2.
Int nodePosition(int j, Int denominator) { return j * denominator / 2; }

// A boundary line's points, each named (a node, or the line's own point k) and handed to the
// sides on it, each side's points in increasing side coordinate; the line's own points' vertex
// requests; and which tile names each node it has.
void Stitcher::resolveBoundaryLine(uint32_t l, Arena& a) {
  const SeamLines::Line& line = lines_.lines[l];
  LineRecord& record = records_[l];
  gatherUses(line, a.line);
  if (a.line.empty()) return;
  record.arena = &a;
  record.ownFrom = uint32_t(a.ownPoints.size());
  if (resolveUniformLine(l, a)) return;
  LinePoints& points = a.points;
  resolveLine(a.line.data(), a.line.size(), points);
  for (int j = 0; j < 3; ++j) {
    if (line.node[j] == kNoSeamNode) continue;
    const Int position = nodePosition(j, points.denominator);
    for (size_t u = 0; u < a.line.size(); ++u) {
      const LineUse& use = a.line[u];
      if (points.lo[u] != position && points.hi[u] != position) continue;
      if (use.tile >= record.claim[j].tile) continue;
      double along, back;
      sideCoordinates(use, points.lo[u], points.hi[u], points.cell[u], position, along, back);
      record.claim[j] = pointOn(use, along);
    }
  }
  writeBoundaryLine(l, a);
}

// The common seam: every side on the line spans all of it (and a side's kept intervals divide the
// densest's cells), so its points are the densest side's, k/cells for k = 0..cells (resolveLine's rule
// comes to that), the ends are its nodes and each end is named by the lowest tile; the first side
// on the line evaluates the own points. Returns false for any other line.
bool Stitcher::resolveUniformLine(uint32_t l, Arena& a) {
  const std::vector<LineUse>& uses = a.line;
  int cells = 0;
  uint32_t lowest = 0;
  for (uint32_t u = 0; u < uses.size(); ++u) {
    const LineUse& use = uses[u];
    if (use.t0 != 0 || use.t1 != kLineScale) return false;
    cells = std::max(cells, use.cells);
    if (use.tile < uses[lowest].tile) lowest = u;
  }
  for (const LineUse& use : uses) {
    if (cells % use.kept != 0) return false;
  }
  const SeamLines::Line& line = lines_.lines[l];
  LineRecord& record = records_[l];
  record.ownCount = uint32_t(cells) - 1;
  const LineUse& lowestUse = uses[lowest];
  for (int j = 0; j <= 2; j += 2) {
    // Node j at t = j/2: the side's coordinate there is 0 or 1, as the side runs along the line.
    const double along = (j == 0) == (lowestUse.sign > 0) ? 0 : 1;
    record.claim[j] = pointOn(lowestUse, along);
  }
  const LineUse& owner = uses[0];
  for (int k = 1; k < cells; ++k) a.ownPoints.push_back(pointOn(owner, double(owner.sign > 0 ? k : cells - k) / cells));
  for (const LineUse& use : uses) {
    boundarySide_[4 * size_t(use.tile) + use.side] = {&a, uint32_t(a.linePool.size()), uint32_t(cells) + 1, l};
    for (int q = 0; q <= cells; ++q) {
      // Point q along the side is point k along the line: node 0, own point k − 1, or node 2.
      const int k = use.sign > 0 ? q : cells - q;
      const double at = double(q) / cells, back = double(cells - q) / cells;
      const int qualifier = boundaryQualifier(use, line, q == 0 || q == cells, at);
      if (k == 0 || k == cells) {
        a.linePool.push_back({line.node[k == 0 ? 0 : 2], Ref::kNode, 0, qualifier, at, back});
      } else {
        a.linePool.push_back({uint32_t(k - 1), Ref::kLineOwn, 0, qualifier, at, back});
      }
    }
  }
  return true;
}

// A resolved line's points (in a.points) named: a node, or the line's own points in order, each
// evaluated by the first side holding it; then each side's points with their side coordinates.
void Stitcher::writeBoundaryLine(uint32_t l, Arena& a) {
  const SeamLines::Line& line = lines_.lines[l];
  LineRecord& record = records_[l];
  const std::vector<LineUse>& uses = a.line;
  LinePoints& points = a.points;
  const size_t count = points.points.size();
  a.resolved.resize(count);
  const std::vector<uint32_t>& order = byStart(points);
  size_t cursor = 0;
  uint32_t own = 0;
  Int nodeAt[3];
  for (int j = 0; j < 3; ++j) nodeAt[j] = line.node[j] == kNoSeamNode ? Int(-1) : nodePosition(j, points.denominator);
  for (size_t p = 0; p < count; ++p) {
    const Int value = points.points[p];
    const int node = value == nodeAt[0] ? 0 : value == nodeAt[1] ? 1 : value == nodeAt[2] ? 2 : -1;
    if (node >= 0) {
      a.resolved[p] = {line.node[node], Ref::kNode, 0, -1, 0, 0};
      continue;
    }
    const size_t owner = holder(points, order, cursor, value);
    const LineUse& use = uses[owner];
    double along, back;
    sideCoordinates(use, points.lo[owner], points.hi[owner], points.cell[owner], value, along, back);
    a.ownPoints.push_back(pointOn(use, along));
    a.resolved[p] = {own++, Ref::kLineOwn, 0, -1, 0, 0};
  }
  record.ownCount = own;
  for (size_t u = 0; u < uses.size(); ++u) {
    const LineUse& use = uses[u];
    const uint32_t begin = uint32_t(std::lower_bound(points.points.begin(), points.points.end(), points.lo[u]) - points.points.begin());
    const uint32_t end = uint32_t(std::upper_bound(points.points.begin() + begin, points.points.end(), points.hi[u]) - points.points.begin());
    const uint32_t n = end - begin;
    boundarySide_[4 * size_t(use.tile) + use.side] = {&a, uint32_t(a.linePool.size()), n, l};
    // Lines run either way along a side: stored with the side's coordinate increasing.
    for (uint32_t q = 0; q < n; ++q) {
      const uint32_t p = use.sign < 0 ? end - 1 - q : begin + q;
      PendingPoint point = a.resolved[p];
      sideCoordinates(use, points.lo[u], points.hi[u], points.cell[u], points.points[p], point.at, point.back);
      point.qualifier = boundaryQualifier(use, line, q == 0 || q + 1 == n, point.at);
      a.linePool.push_back(point);
    }
  }
}

// Seam vertices: the nodes some tile has a corner at (in node order, each evaluated by the lowest
// such tile), then every line's own points, line by line.
void Stitcher::numberSeamVertices() {
  // Per node the lowest claim as (tile, 3 · line + j), packed to compare in one step.
  std::vector<uint64_t> claims(lines_.nodeCount, UINT64_MAX);
  for (size_t l = 0; l < records_.size(); ++l) {
    for (int j = 0; j < 3; ++j) {
      const uint32_t node = lines_.lines[l].node[j];
      if (node == kNoSeamNode || records_[l].claim[j].tile == UINT32_MAX) continue;
      claims[node] = std::min(claims[node], uint64_t(records_[l].claim[j].tile) << 32 | (3 * l + j));
    }
  }
  nodeVertex_.assign(lines_.nodeCount, UINT32_MAX);
  for (uint32_t node = 0; node < lines_.nodeCount; ++node) {
    if (claims[node] == UINT64_MAX) continue;
    const uint32_t lineNode = uint32_t(claims[node] & UINT32_MAX);
    nodeVertex_[node] = uint32_t(nodeVertices_.size());
    nodeVertices_.push_back(records_[lineNode / 3].claim[lineNode % 3]);
  }
  uint32_t next = uint32_t(nodeVertices_.size());
  for (LineRecord& record : records_) {
    record.firstOwn = next;
    next += record.ownCount;
  }
  seamCount_ = next;
}

// How a boundary side's point splits its normal for the side's root: at a root corner as the
// corner says, elsewhere by the face inside an infinitely sharp edge.
int Stitcher::boundaryQualifier(const LineUse& use, const SeamLines::Line& line, bool end, double along) const {
  // A face triangle has no corner that splits its normal and no sharp edge (core/stitching/face_triangles.h).
  if (plan_.tiles[use.tile].faceTriangle) return -1;
  const uint32_t root = tileRoot_[use.tile];
  if (end) {
    const Tile& tile = plan_.tiles[use.tile];
    const int k = use.side;
    const bool high = along == 1;
    const uint32_t c = sideEndCorner(k, high);
    const int64_t x = cornerX(tile, c), y = cornerY(tile, c);
    if ((x == 0 || x == kRootScale) && (y == 0 || y == kRootScale)) {
      const int c = x == 0 ? (y == 0 ? 0 : 3) : (y == 0 ? 1 : 2);
      return lines_.cornerQualifier[4 * size_t(root) + c];
    }
  }
  return line.sharp ? tree_.roots[root].baseFace : -1;
}

// Where the point at `along` of a use is evaluated: in its tile's root on the side's point, or on
// a face triangle's edge in the sub-face whose half holds it.
VertexRequest Stitcher::pointOn(const LineUse& use, double along) const {
  const Tile& tile = plan_.tiles[use.tile];
  if (tile.faceTriangle) return faceEdgePoint(tile, use.tile, along);
  VertexRequest request{use.tile, 0, 0, 0};
  sidePoint(tile, use.side, along, request.u, request.v);
  return request;
}

// A boundary line's point (kNode or kLineOwn) on line `line`: its final vertex.
uint32_t Stitcher::seamVertex(const PendingPoint& point, uint32_t line) const {
  return seamFirst_ + (point.kind == Ref::kNode ? nodeVertex_[point.id] : records_[line].firstOwn + point.id);
}

// Root r's own vertices and its tiles' side points, named for good.
void Stitcher::assembleRoot(uint32_t r) {
  const RootSlice& slice = slices_[r];
  if (slice.arena == nullptr) return;
  std::copy_n(slice.arena->locals.begin() + slice.localsFrom, slice.localsCount, out_.vertices.begin() + localFirst_[r]);
  for (uint32_t v = localFirst_[r]; v < localFirst_[r] + slice.localsCount; ++v) out_.vertices[v].positionOf = v;
  for (uint32_t t = plan_.rootFirstTile[r]; t < plan_.rootFirstTile[r + 1]; ++t) {
    out_.gridFirst[t] = localFirst_[r] + gridLocal_[t];
    for (size_t s = 4 * size_t(t); s < 4 * size_t(t) + 4; ++s) {
      const bool inside = innerSide_[s].count > 0;
      const LineSlot& onLine = boundarySide_[s];
      if (!inside && onLine.count == 0) continue;  // a face triangle's side on no line
      const PendingPoint* side = inside ? slice.arena->pool.data() + innerSide_[s].offset
                                        : onLine.arena->linePool.data() + onLine.offset;
      SidePoint* out = out_.sidePoints.data() + out_.sideFirst[s];
      for (uint32_t q = 0; q < out_.sideFirst[s + 1] - out_.sideFirst[s]; ++q) {
        const PendingPoint& point = side[q];
        SidePoint& result = out[q];
        result = {point.id, point.at, point.back, point.qualifier};
        if (point.kind == Ref::kLocal) result.vertex += localFirst_[r];
        if (point.kind == Ref::kNode || point.kind == Ref::kLineOwn) result.vertex = seamVertex(point, onLine.line);
        if (point.kind == Ref::kSideEnd) {
          const LineSlot& end = boundarySide_[point.id];
          const PendingPoint& corner = end.arena->linePool[end.offset + (point.end ? end.count - 1 : 0)];
          result.vertex = seamVertex(corner, end.line);
          result.qualifier = corner.qualifier;
        }
        if (result.qualifier >= 0) {
          normalClaims_[r].push_back({result.vertex, result.qualifier, t, out_.sideFirst[s] + q, int(s % 4)});
        }
      }
    }
  }
}

// Final vertex ids: each root's own vertices root by root, then the seam vertices (nodes, then
// the lines' own points). Roots and lines are copied into place together, on all cores.
void Stitcher::assemble() {
  localFirst_.resize(slices_.size());
  uint32_t next = 0;
  for (size_t r = 0; r < slices_.size(); ++r) {
    localFirst_[r] = next;
    next += slices_[r].localsCount;
  }
  seamFirst_ = next;
  out_.rootFirstVertex.assign(localFirst_.begin(), localFirst_.end());
  out_.rootFirstVertex.push_back(seamFirst_);
  out_.vertices.resize(next + seamCount_);
  const size_t tiles = plan_.tiles.size();
  out_.sideFirst.assign(4 * tiles + 1, 0);
  out_.gridFirst.resize(tiles);
  for (size_t s = 0; s < 4 * tiles; ++s) {
    out_.sideFirst[s + 1] = out_.sideFirst[s] + (innerSide_[s].count > 0 ? innerSide_[s].count : boundarySide_[s].count);
  }
  out_.sidePoints.resize(out_.sideFirst.back());
  std::copy(nodeVertices_.begin(), nodeVertices_.end(), out_.vertices.begin() + seamFirst_);
  for (uint32_t v = seamFirst_; v < seamFirst_ + nodeVertices_.size(); ++v) out_.vertices[v].positionOf = v;
  const size_t roots = slices_.size();
  normalClaims_.resize(roots);
  // Roots and their lines by the parts that stitched them (parallel_chunks.h): the same cores.
  forOwnedParts(roots, 16, [&](size_t, size_t first, size_t last) {
    for (size_t r = first; r < last; ++r) assembleRoot(uint32_t(r));
    for (uint32_t i = lines_.rootFirstLine[first]; i < lines_.rootFirstLine[last]; ++i) {
      const LineRecord& record = records_[lines_.linesByRoot[i]];
      if (record.ownCount == 0) continue;
      const uint32_t from = seamFirst_ + record.firstOwn;
      std::copy_n(record.arena->ownPoints.begin() + record.ownFrom, record.ownCount, out_.vertices.begin() + from);
      for (uint32_t v = from; v < from + record.ownCount; ++v) out_.vertices[v].positionOf = v;
    }
  });
}

// Across an infinitely sharp edge, and around a vertex that sharp edges cut into wedges, each
// side gets its own vertex: the same position (evaluated once), its own normal.
void Stitcher::splitNormals() {
  std::vector<NormalClaim> claims;
  for (const std::vector<NormalClaim>& root : normalClaims_) claims.insert(claims.end(), root.begin(), root.end());
  std::sort(claims.begin(), claims.end(), [](const NormalClaim& x, const NormalClaim& y) {
    if (x.vertex != y.vertex) return x.vertex < y.vertex;
    if (x.qualifier != y.qualifier) return x.qualifier < y.qualifier;
    return x.tile < y.tile || (x.tile == y.tile && x.sidePoint < y.sidePoint);
  });
  // The qualifier of the tile that evaluates the vertex keeps it; every other one gets a copy,
  // evaluated (for its normal) in the root of its first tile.
  for (size_t i = 0; i < claims.size();) {
    size_t end = i;
    while (end < claims.size() && claims[end].vertex == claims[i].vertex) ++end;
    const uint32_t original = claims[i].vertex;
    const uint32_t owner = out_.vertices[original].tile;
    int keep = claims[i].qualifier;
    for (size_t k = i; k < end; ++k) {
      if (claims[k].tile == owner) keep = claims[k].qualifier;
    }
    for (size_t k = i; k < end;) {
      size_t groupEnd = k;
      while (groupEnd < end && claims[groupEnd].qualifier == claims[k].qualifier) ++groupEnd;
      uint32_t vertex = original;
      if (claims[k].qualifier != keep) {
        vertex = uint32_t(out_.vertices.size());
        VertexRequest copy{claims[k].tile, 0, 0, original};
        sidePoint(plan_.tiles[copy.tile], claims[k].side, out_.sidePoints[claims[k].sidePoint].at, copy.u, copy.v);
        out_.vertices.push_back(copy);
      }
      for (size_t g = k; g < groupEnd; ++g) out_.sidePoints[claims[g].sidePoint].vertex = vertex;
      k = groupEnd;
    }
    i = end;
  }
}

Stitching Stitcher::run() {
  const size_t tiles = plan_.tiles.size(), roots = plan_.rootFirstTile.size() - 1;
  tileRoot_.resize(tiles);
  for (size_t r = 0; r < roots; ++r) {
    std::fill(tileRoot_.begin() + plan_.rootFirstTile[r], tileRoot_.begin() + plan_.rootFirstTile[r + 1], uint32_t(r));
  }
  slices_.resize(roots);
  innerSide_.assign(4 * tiles, {});
  boundarySide_.assign(4 * tiles, {});
  gridLocal_.resize(tiles);
  records_.resize(lines_.lines.size());
  // The roots, then each line by the part that stitched the root of its first side (all of its
  // roots stitched by then). The checkpoint as each part starts and then by work done.
  forOwnedPartsTwice(
      roots, 16,
      [&](size_t, size_t first, size_t last) {
        if (checkpoint_) checkpoint_();
        WorkCheckpoint work(checkpoint_, kWorkPerCheckpoint);
        Arena& a = *arenas_.local().arena;
        for (size_t r = first; r != last; ++r) {
          if (plan_.rootFirstTile[r] < plan_.rootFirstTile[r + 1]) stitchRoot(uint32_t(r), a, work);
        }
      },
      [&](size_t, size_t first, size_t last) {
        if (checkpoint_) checkpoint_();
        WorkCheckpoint work(checkpoint_, kWorkPerCheckpoint);
        Arena& a = *arenas_.local().arena;
        for (uint32_t i = lines_.rootFirstLine[first]; i < lines_.rootFirstLine[last]; ++i) {
          resolveBoundaryLine(lines_.linesByRoot[i], a);
          work.done(1 + a.line.size());  // the line's tile sides
        }
      });
  if (checkpoint_) checkpoint_();
  numberSeamVertices();
  if (checkpoint_) checkpoint_();
  assemble();
  if (checkpoint_) checkpoint_();
  out_.copyFirst = uint32_t(out_.vertices.size());
  splitNormals();
  return std::move(out_);
}

}  // namespace

Stitching stitchTiles(const AdaptivePlan& plan, const SurfaceTree& tree, const SeamLines& lines,
                      const std::function<void()>& checkpoint) {
  return Stitcher(plan, tree, lines, checkpoint).run();
}

}  // namespace tessera
