#include "core/tile_stitching.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <numeric>

namespace tessera {

namespace {

using Int = __int128;

Int gcd(Int a, Int b) {
  if (a < 0) a = -a;
  while (b != 0) {
    const Int r = a % b;
    a = b, b = r;
  }
  return a;
}

// A tile side on its line. Its own grid point k (0..cells) lies at (a + sign·k) / (cells·2^exp)
// of the line's parameter. A line's positions are integers in units of 1/D, D the least common
// multiple of its sides' denominators, so that everything after is integer arithmetic.
struct LineUse {
  Int a = 0;
  int sign = 1, cells = 1, exp = 0;
  bool rigid = false;
  uint32_t tile = 0;
  uint8_t side = 0;
};

// A line's points in units of 1/denominator, and each use's span and cell there.
struct LinePoints {
  Int denominator = 1;
  std::vector<Int> points;
  std::vector<Int> lo, hi, cell;  // per use
  std::vector<uint32_t> order;    // the uses by start (byStart), and room for resolveLine
  std::vector<Int> added;
};

// A line's points: every side's ends, rigid sides' own points, then for each side, densest
// first, its own points wherever two neighbouring points are farther apart than its cell (so
// that no side sees a gap wider than its cells, tile_stitching.h).
void resolveLine(const LineUse* uses, size_t count, LinePoints& out) {
  Int rates = 1;
  int exp = 0;
  for (size_t i = 0; i < count; ++i) {
    rates = rates / gcd(rates, uses[i].cells) * uses[i].cells;
    exp = std::max(exp, uses[i].exp);
  }
  out.denominator = rates << exp;
  out.lo.resize(count), out.hi.resize(count), out.cell.resize(count);
  out.points.clear();
  for (size_t i = 0; i < count; ++i) {
    const LineUse& use = uses[i];
    out.cell[i] = out.denominator / (Int(use.cells) << use.exp);
    const Int p0 = use.a * out.cell[i], p1 = (use.a + use.sign * use.cells) * out.cell[i];
    out.lo[i] = std::min(p0, p1), out.hi[i] = std::max(p0, p1);
    out.points.push_back(out.lo[i]);
    out.points.push_back(out.hi[i]);
    for (int k = 1; use.rigid && k < use.cells; ++k) out.points.push_back(out.lo[i] + k * out.cell[i]);
  }
  auto normalize = [&out] {
    std::sort(out.points.begin(), out.points.end());
    out.points.erase(std::unique(out.points.begin(), out.points.end()), out.points.end());
  };
  normalize();
  if (count == 1 && !uses[0].rigid) {
    // One side (a boundary of the surface): its own points.
    out.points.clear();
    for (int k = 0; k <= uses[0].cells; ++k) out.points.push_back(out.lo[0] + k * out.cell[0]);
    return;
  }
  std::vector<uint32_t>& order = out.order;
  order.resize(count);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&out](uint32_t x, uint32_t y) { return out.cell[x] < out.cell[y]; });
  std::vector<Int>& added = out.added;
  for (uint32_t i : order) {
    added.clear();
    auto p = std::lower_bound(out.points.begin(), out.points.end(), out.lo[i]);
    for (; p + 1 != out.points.end() && *(p + 1) <= out.hi[i]; ++p) {
      if (*(p + 1) - *p <= out.cell[i]) continue;
      for (Int own = out.lo[i] + ((*p - out.lo[i]) / out.cell[i] + 1) * out.cell[i]; own < *(p + 1); own += out.cell[i]) {
        added.push_back(own);
      }
    }
    if (added.empty()) continue;
    out.points.insert(out.points.end(), added.begin(), added.end());
    normalize();
  }
}

// The uses of a line in order of where they start (ties in their given order): walked along with
// the sorted points, the first use holding each point is found in one pass.
const std::vector<uint32_t>& byStart(LinePoints& points) {
  std::vector<uint32_t>& order = points.order;
  order.resize(points.lo.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&points](uint32_t x, uint32_t y) { return points.lo[x] < points.lo[y]; });
  return order;
}

// The first use (in start order from `cursor` on) that holds `value`.
size_t holder(const LinePoints& points, const std::vector<uint32_t>& order, size_t& cursor, Int value) {
  while (points.hi[order[cursor]] < value) ++cursor;
  size_t k = cursor;
  while (!(points.lo[order[k]] <= value && value <= points.hi[order[k]])) ++k;
  return order[k];
}

// Coordinate along a use's side, increasing with u or v, and 1 minus it: exact fractions, rounded.
void sideCoordinates(const LineUse& use, Int lo, Int hi, Int cell, Int point, double& at, double& back) {
  Int fromLo = point - lo, toHi = hi - point;
  if (use.sign < 0) std::swap(fromLo, toHi);
  const Int span = hi - lo;
  if (fromLo % cell == 0) {
    const int k = int(fromLo / cell);
    at = double(k) / use.cells, back = double(use.cells - k) / use.cells;
    return;
  }
  const Int g = gcd(fromLo, span);
  at = double((long double)(fromLo / g) / (long double)(span / g));
  back = double((long double)(toHi / g) / (long double)(span / g));
}

// A vertex reference while roots are stitched: a root's own vertex (local id), or a point on the
// root's boundary (an index into the root's boundary corners, or a global line point).
enum class Ref : uint8_t { kLocal, kCorner, kLinePoint };
struct PendingPoint {
  uint32_t id;
  Ref kind;
  int qualifier;  // normal split for this root (-1: none)
  double at, back;
};

struct BoundaryCorner {
  SeamPoint key;
  uint32_t tile;
  int qualifier;
  double u, v;
};

struct BoundaryUse {
  SeamLine line;
  LineUse use;
  bool sharp;
  int face;
};

// A tile side on a line inside its root: the line is (axis, fixed coordinate).
struct InnerUse {
  int axis;  // 0: u fixed (sides 1, 3), 1: v fixed (sides 0, 2)
  int64_t fixed;
  LineUse use;
};

// Room a thread reuses from root to root.
struct RootScratch {
  std::vector<std::pair<int64_t, int64_t>> inner;
  std::vector<InnerUse> uses;
  std::vector<LineUse> line;
  LinePoints points;
  std::vector<PendingPoint> resolved;
  std::vector<uint32_t> endOf;
};

// What stitching one root produces before the roots are joined.
struct RootStitch {
  std::vector<VertexRequest> locals;  // local vertices: inner corners, inner line points, grids
  std::vector<BoundaryCorner> corners;
  std::vector<BoundaryUse> boundaryUses;
  // Points of the sides inside the root: side k of the root's tile t is sides[4t + k] in pool
  // (count 0: a side on the root's boundary, joined later).
  std::vector<PendingPoint> pool;
  std::vector<std::pair<uint32_t, uint32_t>> sides;
  std::vector<uint32_t> gridFirst;  // local id of each tile's inner grid
};

class Stitcher {
 public:
  Stitcher(const AdaptivePlan& plan, const SurfaceTree& tree, const SeamTopology& seams,
           const std::function<void()>& checkpoint)
      : plan_(plan), tree_(tree), seams_(seams), checkpoint_(checkpoint) {}
  Stitching run();

 private:
  void stitchRoot(uint32_t root, RootStitch& out, RootScratch& scratch) const;
  uint32_t cornerRef(uint32_t root, uint32_t tile, int64_t x, int64_t y, const std::vector<std::pair<int64_t, int64_t>>& inner,
                     RootStitch& out, Ref& kind, int& qualifier) const;
  void joinBoundaries();
  void assemble();
  void splitNormals();

  const AdaptivePlan& plan_;
  const SurfaceTree& tree_;
  const SeamTopology& seams_;
  const std::function<void()>& checkpoint_;
  std::vector<RootStitch> roots_;
  std::vector<uint32_t> localFirst_;               // per root, its first final vertex
  std::vector<std::vector<uint32_t>> cornerIds_;   // per root: boundary corner → final vertex
  std::vector<VertexRequest> seamVertices_;        // boundary corners, then boundary line points
  uint32_t seamFirst_ = 0;
  // Sides on base edges and spokes: tile side 4t + k is boundaryRange_[4t + k] in boundaryPool_.
  std::vector<PendingPoint> boundaryPool_;
  std::vector<std::pair<uint32_t, uint32_t>> boundaryRange_;
  // A side's points wherever they are.
  std::pair<const PendingPoint*, uint32_t> sidePoints(uint32_t root, size_t k) const {
    const auto [offset, count] = roots_[root].sides[k];
    if (count > 0) return {roots_[root].pool.data() + offset, count};
    const auto [boundaryOffset, boundaryCount] = boundaryRange_[4 * size_t(plan_.rootFirstTile[root]) + k];
    return {boundaryPool_.data() + boundaryOffset, boundaryCount};
  }
  Stitching out_;
};

constexpr int64_t at(int level, uint64_t i) { return int64_t(i) << (kRootBits - level); }

// A tile corner: a local vertex inside the root, or a boundary corner.
uint32_t Stitcher::cornerRef(uint32_t root, uint32_t tile, int64_t x, int64_t y,
                             const std::vector<std::pair<int64_t, int64_t>>& inner, RootStitch& out, Ref& kind,
                             int& qualifier) const {
  qualifier = -1;
  if (x > 0 && x < kRootScale && y > 0 && y < kRootScale) {
    kind = Ref::kLocal;
    return uint32_t(std::lower_bound(inner.begin(), inner.end(), std::pair{x, y}) - inner.begin());
  }
  kind = Ref::kCorner;
  const SurfaceRoot& r = tree_.roots[root];
  BoundaryCorner corner;
  corner.key = rootBoundaryPoint(seams_, r.baseFace, r.subFace, x, y, corner.qualifier);
  corner.tile = tile;
  corner.u = std::ldexp(double(x), -kRootBits), corner.v = std::ldexp(double(y), -kRootBits);
  qualifier = corner.qualifier;
  out.corners.push_back(corner);
  return uint32_t(out.corners.size() - 1);
}

// One root: its inner corners and the lines inside it are resolved here; its sides on base edges
// and spokes wait for the other roots there (joinBoundaries).
void Stitcher::stitchRoot(uint32_t root, RootStitch& out, RootScratch& scratch) const {
  const uint32_t first = plan_.rootFirstTile[root], last = plan_.rootFirstTile[root + 1];
  const SurfaceRoot& r = tree_.roots[root];
  out.sides.assign(4 * size_t(last - first), {0, 0});
  // Inner corners, numbered in (x, y) order.
  std::vector<std::pair<int64_t, int64_t>>& inner = scratch.inner;
  inner.clear();
  for (uint32_t t = first; t < last; ++t) {
    const Tile& tile = plan_.tiles[t];
    for (int c = 0; c < 4; ++c) {
      const int64_t x = at(tile.level, tile.ix + (c == 1 || c == 2)), y = at(tile.level, tile.iy + (c >= 2));
      if (x > 0 && x < kRootScale && y > 0 && y < kRootScale) inner.push_back({x, y});
    }
  }
  std::sort(inner.begin(), inner.end());
  inner.erase(std::unique(inner.begin(), inner.end()), inner.end());
  // Every tile corner on the root's boundary is named, whatever sides meet there.
  for (uint32_t t = first; t < last; ++t) {
    const Tile& tile = plan_.tiles[t];
    for (int c = 0; c < 4; ++c) {
      const int64_t x = at(tile.level, tile.ix + (c == 1 || c == 2)), y = at(tile.level, tile.iy + (c >= 2));
      Ref kind;
      int qualifier;
      if (!(x > 0 && x < kRootScale && y > 0 && y < kRootScale)) cornerRef(root, t, x, y, inner, out, kind, qualifier);
    }
  }
  for (const auto& [x, y] : inner) {
    out.locals.push_back({UINT32_MAX, std::ldexp(double(x), -kRootBits), std::ldexp(double(y), -kRootBits), 0});
  }
  // Sides: inside the root they go on lines keyed (axis, fixed coordinate); on its boundary they
  // wait for joinBoundaries.
  std::vector<InnerUse>& uses = scratch.uses;
  uses.clear();
  for (uint32_t t = first; t < last; ++t) {
    const Tile& tile = plan_.tiles[t];
    const uint64_t end = uint64_t(1) << tile.level;
    const bool strip = (tile.ru == 1) != (tile.rv == 1);
    for (int k = 0; k < 4; ++k) {
      const bool alongU = k == 0 || k == 2;
      LineUse use;
      use.cells = alongU ? tile.ru : tile.rv;
      use.exp = tile.level;
      use.rigid = strip && use.cells > 1;
      use.tile = t;
      use.side = uint8_t(k);
      const uint64_t along = alongU ? tile.ix : tile.iy;
      const bool onBoundary = k == 0 ? tile.iy == 0 : k == 1 ? tile.ix + 1 == end : k == 2 ? tile.iy + 1 == end : tile.ix == 0;
      if (onBoundary) {
        const SideLine line = rootSideLine(seams_, r.baseFace, r.subFace, k);
        const int d = line.halves == 2 ? 1 : 0;
        use.a = (Int(line.origin) * use.cells << (tile.level + d)) + line.sign * Int(along) * use.cells;
        use.sign = line.sign;
        use.exp = tile.level + d;
        out.boundaryUses.push_back({line.line, use, line.sharp, r.baseFace});
        continue;
      }
      use.a = Int(along) * use.cells;
      const uint64_t fixedIndex = k == 0 ? tile.iy : k == 1 ? tile.ix + 1 : k == 2 ? tile.iy + 1 : tile.ix;
      uses.push_back({alongU ? 1 : 0, at(tile.level, fixedIndex), use});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const InnerUse& x, const InnerUse& y) {
    if (x.axis != y.axis) return x.axis < y.axis;
    if (x.fixed != y.fixed) return x.fixed < y.fixed;
    return x.use.tile < y.use.tile || (x.use.tile == y.use.tile && x.use.side < y.use.side);
  });
  std::vector<LineUse>& line = scratch.line;
  LinePoints& points = scratch.points;
  std::vector<PendingPoint>& resolved = scratch.resolved;
  std::vector<uint32_t>& endOf = scratch.endOf;
  for (size_t i = 0; i < uses.size();) {
    size_t j = i;
    line.clear();
    while (j < uses.size() && uses[j].axis == uses[i].axis && uses[j].fixed == uses[i].fixed) line.push_back(uses[j++].use);
    resolveLine(line.data(), line.size(), points);
    // Each point: a tile corner (the end of some side) or the line's own vertex.
    resolved.assign(points.points.size(), {0, Ref::kLocal, -1, 0, 0});
    // A point that ends a side is that side's tile corner (0: not an end).
    endOf.assign(points.points.size(), 0);
    for (size_t u = 0; u < line.size(); ++u) {
      for (const Int end : {points.lo[u], points.hi[u]}) {
        endOf[std::lower_bound(points.points.begin(), points.points.end(), end) - points.points.begin()] = line[u].tile + 1;
      }
    }
    const std::vector<uint32_t>& order = byStart(points);
    size_t cursor = 0;
    for (size_t p = 0; p < points.points.size(); ++p) {
      const Int value = points.points[p];
      // Position along the line at kRootScale (exact for tile corners, which are dyadic).
      const Int scaled = (value << kRootBits) / points.denominator;
      const int64_t x = uses[i].axis == 1 ? int64_t(scaled) : uses[i].fixed;
      const int64_t y = uses[i].axis == 1 ? uses[i].fixed : int64_t(scaled);
      PendingPoint& point = resolved[p];
      if (endOf[p] != 0) {
        point.id = cornerRef(root, endOf[p] - 1, x, y, inner, out, point.kind, point.qualifier);
        continue;
      }
      const size_t owner = holder(points, order, cursor, value);
      point.id = uint32_t(out.locals.size());
      const double along = double((long double)value / (long double)points.denominator);
      const double fixed = std::ldexp(double(uses[i].fixed), -kRootBits);
      out.locals.push_back({line[owner].tile, uses[i].axis == 1 ? along : fixed, uses[i].axis == 1 ? fixed : along, 0});
    }
    for (size_t u = 0; u < line.size(); ++u) {
      const auto from = std::lower_bound(points.points.begin(), points.points.end(), points.lo[u]) - points.points.begin();
      const auto to = std::upper_bound(points.points.begin(), points.points.end(), points.hi[u]) - points.points.begin();
      out.sides[4 * size_t(line[u].tile - first) + line[u].side] = {uint32_t(out.pool.size()), uint32_t(to - from)};
      for (auto p = from; p < to; ++p) {
        PendingPoint point = resolved[p];
        sideCoordinates(line[u], points.lo[u], points.hi[u], points.cell[u], points.points[p], point.at, point.back);
        out.pool.push_back(point);
      }
    }
    i = j;
  }
  out.gridFirst.resize(last - first);
  for (uint32_t t = first; t < last; ++t) {
    const Tile& tile = plan_.tiles[t];
    out.gridFirst[t - first] = uint32_t(out.locals.size());
    const double s = tile.size();
    for (int j = 1; j < tile.rv; ++j) {
      for (int i = 1; i < tile.ru; ++i) {
        out.locals.push_back({t, (double(tile.ix) + double(i) / tile.ru) * s, (double(tile.iy) + double(j) / tile.rv) * s, 0});
      }
    }
  }
  // Inner corners take the first tile that has one as the tile that evaluates it.
  for (uint32_t t = first; t < last; ++t) {
    const Tile& tile = plan_.tiles[t];
    for (int c = 0; c < 4; ++c) {
      const int64_t x = at(tile.level, tile.ix + (c == 1 || c == 2)), y = at(tile.level, tile.iy + (c >= 2));
      if (!(x > 0 && x < kRootScale && y > 0 && y < kRootScale)) continue;
      VertexRequest& request = out.locals[std::lower_bound(inner.begin(), inner.end(), std::pair{x, y}) - inner.begin()];
      request.tile = std::min(request.tile, t);
    }
  }
}

// Base edges and spokes: each root's sides there joined with the other root's, and every
// boundary corner named once.
void Stitcher::joinBoundaries() {
  struct CornerRef {
    SeamPoint key;
    uint32_t root, index;
  };
  std::vector<CornerRef> refs;
  for (uint32_t r = 0; r < roots_.size(); ++r) {
    for (uint32_t i = 0; i < roots_[r].corners.size(); ++i) refs.push_back({roots_[r].corners[i].key, r, i});
  }
  tbb::parallel_sort(refs.begin(), refs.end(), [this](const CornerRef& x, const CornerRef& y) {
    if (!(x.key == y.key)) return x.key < y.key;
    return roots_[x.root].corners[x.index].tile < roots_[y.root].corners[y.index].tile;
  });
  cornerIds_.resize(roots_.size());
  for (uint32_t r = 0; r < roots_.size(); ++r) cornerIds_[r].resize(roots_[r].corners.size());
  std::vector<SeamPoint> keys;
  for (size_t i = 0; i < refs.size(); ++i) {
    if (i == 0 || !(refs[i].key == refs[i - 1].key)) {
      keys.push_back(refs[i].key);
      const BoundaryCorner& c = roots_[refs[i].root].corners[refs[i].index];
      seamVertices_.push_back({c.tile, c.u, c.v, 0});
    }
    cornerIds_[refs[i].root][refs[i].index] = uint32_t(keys.size() - 1);
  }
  // Boundary uses, line by line.
  struct Seam {
    BoundaryUse use;
    uint32_t root;
  };
  std::vector<Seam> seams;
  for (uint32_t r = 0; r < roots_.size(); ++r) {
    for (const BoundaryUse& use : roots_[r].boundaryUses) seams.push_back({use, r});
  }
  tbb::parallel_sort(seams.begin(), seams.end(), [](const Seam& x, const Seam& y) {
    if (!(x.use.line == y.use.line)) return x.use.line < y.use.line;
    return x.use.use.tile < y.use.use.tile || (x.use.use.tile == y.use.use.tile && x.use.use.side < y.use.use.side);
  });
  // Lines, resolved on all cores; their own points numbered line by line afterwards.
  std::vector<std::pair<size_t, size_t>> lines;  // seam ranges
  for (size_t i = 0; i < seams.size();) {
    size_t j = i;
    while (j < seams.size() && seams[j].use.line == seams[i].use.line) ++j;
    lines.push_back({i, j});
    i = j;
  }
  struct Resolved {
    LinePoints points;
    std::vector<uint8_t> isEnd;
    uint32_t ownPoints = 0, firstOwn = 0;
    std::vector<uint32_t> useFrom, useTo;  // each use's range of points
  };
  std::vector<Resolved> resolved(lines.size());
  tbb::parallel_for(size_t(0), lines.size(), [&](size_t l) {
    Resolved& line = resolved[l];
    std::vector<LineUse> uses;
    for (size_t i = lines[l].first; i < lines[l].second; ++i) uses.push_back(seams[i].use.use);
    resolveLine(uses.data(), uses.size(), line.points);
    const std::vector<Int>& p = line.points.points;
    line.isEnd.assign(p.size(), 0);
    for (size_t u = 0; u < uses.size(); ++u) {
      line.useFrom.push_back(uint32_t(std::lower_bound(p.begin(), p.end(), line.points.lo[u]) - p.begin()));
      line.useTo.push_back(uint32_t(std::upper_bound(p.begin(), p.end(), line.points.hi[u]) - p.begin()));
      line.isEnd[line.useFrom.back()] = line.isEnd[line.useTo.back() - 1] = 1;
    }
    for (uint8_t end : line.isEnd) line.ownPoints += end ? 0 : 1;
  });
  boundaryRange_.assign(4 * plan_.tiles.size(), {0, 0});
  uint32_t poolSize = 0, nextVertex = uint32_t(seamVertices_.size());
  for (size_t l = 0; l < lines.size(); ++l) {
    resolved[l].firstOwn = nextVertex;
    nextVertex += resolved[l].ownPoints;
    for (size_t u = 0; u < resolved[l].useFrom.size(); ++u) {
      const LineUse& use = seams[lines[l].first + u].use.use;
      const uint32_t count = resolved[l].useTo[u] - resolved[l].useFrom[u];
      boundaryRange_[4 * size_t(use.tile) + use.side] = {poolSize, count};
      poolSize += count;
    }
  }
  seamVertices_.resize(nextVertex);
  boundaryPool_.resize(poolSize);
  tbb::parallel_for(size_t(0), lines.size(), [&](size_t l) {
    const Resolved& line = resolved[l];
    const LinePoints& points = line.points;
    const size_t uses = line.useFrom.size();
    auto useOf = [&](size_t u) -> const LineUse& { return seams[lines[l].first + u].use.use; };
    std::vector<uint32_t> ids(points.points.size());
    LinePoints& mutablePoints = resolved[l].points;
    const std::vector<uint32_t>& order = byStart(mutablePoints);
    size_t cursor = 0;
    uint32_t nextOwn = line.firstOwn;
    for (size_t p = 0; p < points.points.size(); ++p) {
      const Int value = points.points[p];
      if (line.isEnd[p]) {
        const SeamPoint key = pointOnLine(seams_, seams[lines[l].first].use.line, int64_t((value << kLineBits) / points.denominator));
        ids[p] = uint32_t(std::lower_bound(keys.begin(), keys.end(), key) - keys.begin());
        continue;
      }
      const size_t owner = holder(points, order, cursor, value);
      const LineUse& use = useOf(owner);
      const Tile& tile = plan_.tiles[use.tile];
      double along, back;
      sideCoordinates(use, points.lo[owner], points.hi[owner], points.cell[owner], value, along, back);
      const double size = tile.size();
      const bool alongU = use.side == 0 || use.side == 2;
      const double u = alongU ? (double(tile.ix) + along) * size : (double(tile.ix) + (use.side == 1)) * size;
      const double v = alongU ? (double(tile.iy) + (use.side == 2)) * size : (double(tile.iy) + along) * size;
      ids[p] = nextOwn++;
      seamVertices_[ids[p]] = {use.tile, u, v, 0};
    }
    for (size_t u = 0; u < uses; ++u) {
      const Seam& seam = seams[lines[l].first + u];
      const LineUse& use = seam.use.use;
      PendingPoint* out = boundaryPool_.data() + boundaryRange_[4 * size_t(use.tile) + use.side].first;
      const uint32_t from = line.useFrom[u], to = line.useTo[u];
      for (uint32_t p = from; p < to; ++p) {
        PendingPoint point{ids[p], Ref::kLinePoint, -1, 0, 0};
        sideCoordinates(use, points.lo[u], points.hi[u], points.cell[u], points.points[p], point.at, point.back);
        if (p == from || p + 1 == to) {
          // The side's own corner: its root decides the split (a wedge at a base vertex, the face
          // inside a sharp edge).
          const Tile& tile = plan_.tiles[use.tile];
          const int k = use.side;
          const bool high = point.at == 1;
          const uint64_t ix = tile.ix + ((k == 1) || ((k == 0 || k == 2) && high) ? 1 : 0);
          const uint64_t iy = tile.iy + ((k == 2) || ((k == 1 || k == 3) && high) ? 1 : 0);
          const SurfaceRoot& root = tree_.roots[seam.root];
          rootBoundaryPoint(seams_, root.baseFace, root.subFace, at(tile.level, ix), at(tile.level, iy), point.qualifier);
        } else if (seam.use.sharp) {
          point.qualifier = seam.use.face;
        }
        out[p - from] = point;
      }
    }
  });
}

// Final vertex ids: each root's own vertices root by root, then the seams' points.
void Stitcher::assemble() {
  localFirst_.resize(roots_.size());
  uint32_t next = 0;
  for (uint32_t r = 0; r < roots_.size(); ++r) {
    localFirst_[r] = next;
    next += uint32_t(roots_[r].locals.size());
  }
  seamFirst_ = next;
  out_.vertices.resize(next + seamVertices_.size());
  for (uint32_t r = 0; r < roots_.size(); ++r) {
    std::copy(roots_[r].locals.begin(), roots_[r].locals.end(), out_.vertices.begin() + localFirst_[r]);
  }
  std::copy(seamVertices_.begin(), seamVertices_.end(), out_.vertices.begin() + seamFirst_);
  for (uint32_t v = 0; v < out_.vertices.size(); ++v) out_.vertices[v].positionOf = v;
  const size_t tiles = plan_.tiles.size();
  out_.sideFirst.assign(4 * tiles + 1, 0);
  out_.gridFirst.resize(tiles);
  for (uint32_t r = 0; r < roots_.size(); ++r) {
    const uint32_t first = plan_.rootFirstTile[r];
    for (size_t k = 0; k < roots_[r].sides.size(); ++k) {
      out_.sideFirst[4 * size_t(first) + k + 1] = sidePoints(r, k).second;
    }
    for (size_t t = 0; t < roots_[r].gridFirst.size(); ++t) out_.gridFirst[first + t] = localFirst_[r] + roots_[r].gridFirst[t];
  }
  std::partial_sum(out_.sideFirst.begin(), out_.sideFirst.end(), out_.sideFirst.begin());
  out_.sidePoints.resize(out_.sideFirst.back());
  tbb::parallel_for(size_t(0), roots_.size(), [&](size_t r) {
    const uint32_t first = plan_.rootFirstTile[r];
    for (size_t k = 0; k < roots_[r].sides.size(); ++k) {
      const size_t s = 4 * size_t(first) + k;
      const auto [side, count] = sidePoints(uint32_t(r), k);
      // Lines run either way along a side: stored with the side's coordinate increasing.
      const bool reversed = count > 1 && side[0].at > side[count - 1].at;
      SidePoint* out = out_.sidePoints.data() + out_.sideFirst[s];
      for (size_t q = 0; q < count; ++q) {
        const size_t p = reversed ? count - 1 - q : q;
        const PendingPoint& point = side[q];
        uint32_t id = point.id;
        if (point.kind == Ref::kLocal) id += localFirst_[r];
        if (point.kind == Ref::kCorner) id = seamFirst_ + cornerIds_[r][point.id];
        if (point.kind == Ref::kLinePoint) id += seamFirst_;
        out[p] = {id, point.at, point.back, point.qualifier};
      }
    }
  });
}

// Across an infinitely sharp edge, and around a vertex that sharp edges cut into wedges, each
// side gets its own vertex: the same position (evaluated once), its own normal.
void Stitcher::splitNormals() {
  struct Claim {
    uint32_t vertex;
    int qualifier;
    uint32_t tile, sidePoint;
    int side;
  };
  std::vector<Claim> claims;
  for (size_t t = 0; t < plan_.tiles.size(); ++t) {
    for (int k = 0; k < 4; ++k) {
      for (uint32_t index = out_.sideFirst[4 * t + k]; index < out_.sideFirst[4 * t + k + 1]; ++index) {
        const SidePoint& point = out_.sidePoints[index];
        if (point.qualifier >= 0) claims.push_back({point.vertex, point.qualifier, uint32_t(t), index, k});
      }
    }
  }
  std::sort(claims.begin(), claims.end(), [](const Claim& x, const Claim& y) {
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
        const Tile& tile = plan_.tiles[claims[k].tile];
        const int side = claims[k].side;
        const double s = tile.size(), along = out_.sidePoints[claims[k].sidePoint].at;
        const bool alongU = side == 0 || side == 2;
        const double u = alongU ? (double(tile.ix) + along) * s : (double(tile.ix) + (side == 1)) * s;
        const double v = alongU ? (double(tile.iy) + (side == 2)) * s : (double(tile.iy) + along) * s;
        out_.vertices.push_back({claims[k].tile, u, v, original});
      }
      for (size_t g = k; g < groupEnd; ++g) out_.sidePoints[claims[g].sidePoint].vertex = vertex;
      k = groupEnd;
    }
    i = end;
  }
}

Stitching Stitcher::run() {
  roots_.resize(tree_.roots.size());
  tbb::enumerable_thread_specific<RootScratch> scratch;
  tbb::parallel_for(size_t(0), roots_.size(), [&](size_t r) {
    if (checkpoint_ && r % 256 == 0) checkpoint_();
    if (plan_.rootFirstTile[r] < plan_.rootFirstTile[r + 1]) stitchRoot(uint32_t(r), roots_[r], scratch.local());
  });
  joinBoundaries();
  if (checkpoint_) checkpoint_();
  assemble();
  splitNormals();
  return std::move(out_);
}

}  // namespace

Stitching stitchTiles(const AdaptivePlan& plan, const SurfaceTree& tree, const SeamTopology& seams,
                      const std::function<void()>& checkpoint) {
  return Stitcher(plan, tree, seams, checkpoint).run();
}

}  // namespace tessera
