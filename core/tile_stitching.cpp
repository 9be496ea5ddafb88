#include "core/tile_stitching.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <numeric>

namespace tessera {

namespace {

const Fraction kZero{0, 1}, kOne{1, 1};

// floor(x / y) for positive y, exactly.
int64_t floorDiv(const Fraction& x, const Fraction& y) {
  const __int128 n = __int128(x.num) * y.den, d = __int128(x.den) * y.num;
  __int128 q = n / d;
  if ((n % d != 0) && ((n < 0) != (d < 0))) --q;
  return int64_t(q);
}

// One tile side on its line: [a, b] there (a < b), its own cell `step`, `cells` of them.
struct Use {
  LineKey line;
  Fraction a, b, step;
  uint32_t tile;
  uint16_t cells;
  uint8_t side;
  bool rigid, reversed;
};

// The exact root coordinates of a tile: its square [x0, x0 + size]² and grid points.
struct TileFrame {
  int face, subFace;
  Fraction x0, y0, size;

  TileFrame(const Tile& t, const SurfaceRoot& root)
      : face(root.baseFace), subFace(root.subFace),
        x0(Fraction::make(int64_t(t.ix), int64_t(1) << t.level)),
        y0(Fraction::make(int64_t(t.iy), int64_t(1) << t.level)),
        size(Fraction::make(1, int64_t(1) << t.level)) {}
  // Root (u, v) of the point at coordinate c ∈ [0, 1] along side k (sides 0, 2 along u).
  void onSide(int k, const Fraction& c, Fraction& u, Fraction& v) const {
    const Fraction along = size.times(c.num).over(c.den);  // c·size, exactly
    if (k == 0 || k == 2) {
      u = x0 + along, v = k == 0 ? y0 : y0 + size;
    } else {
      v = y0 + along, u = k == 3 ? x0 : x0 + size;
    }
  }
};

class Stitcher {
 public:
  Stitcher(const AdaptivePlan& plan, const SurfaceTree& tree, const SeamTopology& seams,
           const std::function<void()>& checkpoint)
      : plan_(plan), tree_(tree), seams_(seams), checkpoint_(checkpoint) {}
  Stitching run();

 private:
  struct Line {
    uint32_t firstUse, useCount;
    uint32_t firstPoint, pointCount;  // into points_
  };
  TileFrame frameOf(size_t tile) const { return TileFrame(plan_.tiles[tile], tree_.roots[tileRoot_[tile]]); }
  void collectUses();
  std::vector<Fraction> resolveLine(const Use* uses, uint32_t count) const;
  void resolveLines();
  void numberCorners();
  void numberLinePoints();
  void buildSides();
  uint32_t cornerVertex(const PointKey& key) const;
  PointKey keyOnLine(const Use& use, const Fraction& t) const;
  Fraction sideCoordinate(const Use& use, const Fraction& t) const;
  void splitNormals();

  const AdaptivePlan& plan_;
  const SurfaceTree& tree_;
  const SeamTopology& seams_;
  const std::function<void()>& checkpoint_;
  std::vector<uint32_t> tileRoot_;
  std::vector<Use> uses_;  // sorted by line, then a
  std::vector<Line> lines_;
  std::vector<Fraction> points_;      // each line's points, sorted
  std::vector<uint8_t> pointIsEnd_;   // a side's end (a tile corner) rather than a line's own point
  std::vector<uint32_t> pointVertex_;
  std::vector<PointKey> cornerKeys_;  // sorted, unique: vertex i is corner key i
  Stitching out_;
};

void Stitcher::collectUses() {
  const size_t tiles = plan_.tiles.size();
  tileRoot_.resize(tiles);
  for (size_t r = 0; r + 1 < plan_.rootFirstTile.size(); ++r) {
    std::fill(tileRoot_.begin() + plan_.rootFirstTile[r], tileRoot_.begin() + plan_.rootFirstTile[r + 1], uint32_t(r));
  }
  uses_.resize(4 * tiles);
  tbb::parallel_for(size_t(0), tiles, [&](size_t t) {
    const Tile& tile = plan_.tiles[t];
    const TileFrame frame = frameOf(t);
    const uint64_t last = (uint64_t(1) << tile.level) - 1;
    const bool onRoot[4] = {tile.iy == 0, tile.ix == last, tile.iy == last, tile.ix == 0};
    // One-cell-wide strips keep their long sides' points: their cells then meet those sides exactly.
    const bool strip = (tile.ru == 1) != (tile.rv == 1);
    for (int k = 0; k < 4; ++k) {
      Use& use = uses_[4 * t + k];
      Fraction u0, v0, u1, v1;
      frame.onSide(k, kZero, u0, v0);
      frame.onSide(k, kOne, u1, v1);
      const bool alongU = k == 0 || k == 2;
      Fraction s0 = alongU ? u0 : v0, s1 = alongU ? u1 : v1, ta, tb;
      if (onRoot[k]) {
        const SideLine side = rootSideLine(seams_, frame.face, frame.subFace, k);
        use.line = side.line;
        ta = side.at(s0), tb = side.at(s1);
      } else {
        use.line = {LineKey::kInterior, uint8_t(alongU ? 1 : 0), int(tileRoot_[t]), 0, alongU ? v0 : u0};
        ta = s0, tb = s1;
      }
      use.reversed = tb < ta;
      use.a = use.reversed ? tb : ta;
      use.b = use.reversed ? ta : tb;
      use.cells = uint16_t(alongU ? tile.ru : tile.rv);
      use.step = (use.b - use.a).over(use.cells);
      use.tile = uint32_t(t);
      use.side = uint8_t(k);
      use.rigid = strip && (alongU ? tile.ru > 1 : tile.rv > 1);
    }
  });
  tbb::parallel_sort(uses_.begin(), uses_.end(), [](const Use& x, const Use& y) {
    if (!(x.line == y.line)) return x.line < y.line;
    if (!(x.a == y.a)) return x.a < y.a;
    return x.tile < y.tile || (x.tile == y.tile && x.side < y.side);
  });
  for (uint32_t u = 0; u < uses_.size(); ++u) {
    if (u == 0 || !(uses_[u].line == uses_[u - 1].line)) lines_.push_back({u, 0, 0, 0});
    ++lines_.back().useCount;
  }
}

// A line's points: every side's ends, rigid sides' own points, then for each side, densest
// first, its own points wherever two neighbouring points are farther apart than its cell.
std::vector<Fraction> Stitcher::resolveLine(const Use* uses, uint32_t count) const {
  std::vector<Fraction> points;
  for (uint32_t i = 0; i < count; ++i) {
    points.push_back(uses[i].a);
    points.push_back(uses[i].b);
    for (int k = 1; uses[i].rigid && k < uses[i].cells; ++k) points.push_back(uses[i].a + uses[i].step.times(k));
  }
  auto normalize = [&points] {
    std::sort(points.begin(), points.end());
    points.erase(std::unique(points.begin(), points.end()), points.end());
  };
  normalize();
  std::vector<uint32_t> order(count);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [uses](uint32_t x, uint32_t y) { return uses[x].step < uses[y].step; });
  std::vector<Fraction> added;
  for (uint32_t i : order) {
    const Use& use = uses[i];
    added.clear();
    auto p = std::lower_bound(points.begin(), points.end(), use.a);
    for (; p + 1 != points.end() && *(p + 1) <= use.b; ++p) {
      if ((*(p + 1) - *p) <= use.step) continue;
      for (int64_t k = floorDiv(*p - use.a, use.step) + 1;; ++k) {
        const Fraction own = use.a + use.step.times(k);
        if (!(own < *(p + 1))) break;
        added.push_back(own);
      }
    }
    if (added.empty()) continue;
    points.insert(points.end(), added.begin(), added.end());
    normalize();
  }
  return points;
}

void Stitcher::resolveLines() {
  std::vector<std::vector<Fraction>> perLine(lines_.size());
  tbb::parallel_for(size_t(0), lines_.size(), [&](size_t l) {
    if (checkpoint_ && l % 4096 == 0) checkpoint_();
    perLine[l] = resolveLine(uses_.data() + lines_[l].firstUse, lines_[l].useCount);
  });
  for (size_t l = 0; l < lines_.size(); ++l) {
    lines_[l].firstPoint = uint32_t(points_.size());
    lines_[l].pointCount = uint32_t(perLine[l].size());
    points_.insert(points_.end(), perLine[l].begin(), perLine[l].end());
  }
  pointIsEnd_.assign(points_.size(), 0);
  tbb::parallel_for(size_t(0), lines_.size(), [&](size_t l) {
    const Line& line = lines_[l];
    const Fraction* first = points_.data() + line.firstPoint;
    const Fraction* last = first + line.pointCount;
    for (uint32_t u = line.firstUse; u < line.firstUse + line.useCount; ++u) {
      for (const Fraction& end : {uses_[u].a, uses_[u].b}) pointIsEnd_[std::lower_bound(first, last, end) - points_.data()] = 1;
    }
  });
}

// Tile corners: one vertex per distinct point, numbered in key order, evaluated by the first tile
// (in plan order) that has it.
void Stitcher::numberCorners() {
  struct CornerRef {
    PointKey key;
    uint32_t tile;
    uint8_t corner;
  };
  const size_t tiles = plan_.tiles.size();
  std::vector<CornerRef> refs(4 * tiles);
  tbb::parallel_for(size_t(0), tiles, [&](size_t t) {
    const TileFrame frame = frameOf(t);
    for (int c = 0; c < 4; ++c) {
      const Fraction u = c == 1 || c == 2 ? frame.x0 + frame.size : frame.x0;
      const Fraction v = c >= 2 ? frame.y0 + frame.size : frame.y0;
      refs[4 * t + c] = {rootPointKey(seams_, frame.face, frame.subFace, u, v), uint32_t(t), uint8_t(c)};
    }
  });
  tbb::parallel_sort(refs.begin(), refs.end(), [](const CornerRef& x, const CornerRef& y) {
    if (!(x.key == y.key)) return x.key < y.key;
    return x.tile < y.tile;
  });
  for (size_t i = 0; i < refs.size(); ++i) {
    if (i > 0 && refs[i].key == refs[i - 1].key) continue;
    cornerKeys_.push_back(refs[i].key);
    const Tile& tile = plan_.tiles[refs[i].tile];
    const double s = tile.size();
    const int c = refs[i].corner;
    const uint32_t id = uint32_t(out_.vertices.size());
    out_.vertices.push_back({refs[i].tile, (double(tile.ix) + (c == 1 || c == 2)) * s, (double(tile.iy) + (c >= 2)) * s, id});
  }
}

uint32_t Stitcher::cornerVertex(const PointKey& key) const {
  return uint32_t(std::lower_bound(cornerKeys_.begin(), cornerKeys_.end(), key) - cornerKeys_.begin());
}

PointKey Stitcher::keyOnLine(const Use& use, const Fraction& t) const {
  const SurfaceRoot& root = tree_.roots[tileRoot_[use.tile]];
  return linePointKey(seams_, use.line, t, root.baseFace, root.subFace);
}

// Coordinate in [0, 1] along a use's side, increasing with u or v.
Fraction Stitcher::sideCoordinate(const Use& use, const Fraction& t) const {
  const Fraction along = (t - use.a) / (use.b - use.a);
  return use.reversed ? kOne - along : along;
}

// A line's own points (not tile corners), numbered line by line, each evaluated by the first side
// (in line order) that holds it.
void Stitcher::numberLinePoints() {
  pointVertex_.resize(points_.size());
  for (const Line& line : lines_) {
    const Fraction* first = points_.data() + line.firstPoint;
    uint32_t u = line.firstUse;
    for (uint32_t p = 0; p < line.pointCount; ++p) {
      const uint32_t index = line.firstPoint + p;
      if (pointIsEnd_[index]) {
        pointVertex_[index] = cornerVertex(keyOnLine(uses_[line.firstUse], first[p]));
        continue;
      }
      while (!(uses_[u].a <= first[p] && first[p] <= uses_[u].b)) ++u;
      const Use& use = uses_[u];
      const TileFrame frame = frameOf(use.tile);
      Fraction ru, rv;
      frame.onSide(use.side, sideCoordinate(use, first[p]), ru, rv);
      pointVertex_[index] = uint32_t(out_.vertices.size());
      out_.vertices.push_back({use.tile, ru.value(), rv.value(), pointVertex_[index]});
    }
  }
}

// Each tile side's points, from its line, in increasing side coordinate; then the inner grids.
void Stitcher::buildSides() {
  const size_t tiles = plan_.tiles.size();
  std::vector<uint32_t> counts(4 * tiles + 1, 0);
  std::vector<std::pair<uint32_t, uint32_t>> ranges(4 * tiles);  // side → [first, last) in points_
  tbb::parallel_for(size_t(0), lines_.size(), [&](size_t l) {
    const Line& line = lines_[l];
    const Fraction* first = points_.data() + line.firstPoint;
    const Fraction* last = first + line.pointCount;
    for (uint32_t u = line.firstUse; u < line.firstUse + line.useCount; ++u) {
      const Use& use = uses_[u];
      const uint32_t from = uint32_t(std::lower_bound(first, last, use.a) - points_.data());
      const uint32_t to = uint32_t(std::upper_bound(first, last, use.b) - points_.data());
      ranges[4 * size_t(use.tile) + use.side] = {from, to};
      counts[4 * size_t(use.tile) + use.side] = to - from;
    }
  });
  out_.sideFirst.resize(4 * tiles + 1);
  std::exclusive_scan(counts.begin(), counts.end(), out_.sideFirst.begin(), 0u);
  out_.sidePoints.resize(out_.sideFirst.back());
  std::vector<const Use*> useOf(4 * tiles);
  for (const Use& use : uses_) useOf[4 * size_t(use.tile) + use.side] = &use;
  tbb::parallel_for(size_t(0), 4 * tiles, [&](size_t s) {
    const Use& use = *useOf[s];
    const auto [from, to] = ranges[s];
    SidePoint* out = out_.sidePoints.data() + out_.sideFirst[s];
    for (uint32_t p = from; p < to; ++p) {
      const Fraction at = sideCoordinate(use, points_[p]);
      out[use.reversed ? to - 1 - p : p - from] = {pointVertex_[p], at.value(), (kOne - at).value()};
    }
  });
  out_.gridFirst.resize(tiles);
  for (size_t t = 0; t < tiles; ++t) {
    const Tile& tile = plan_.tiles[t];
    out_.gridFirst[t] = uint32_t(out_.vertices.size());
    const double s = tile.size();
    for (int j = 1; j < tile.rv; ++j) {
      for (int i = 1; i < tile.ru; ++i) {
        out_.vertices.push_back({uint32_t(t), (double(tile.ix) + double(i) / tile.ru) * s,
                                 (double(tile.iy) + double(j) / tile.rv) * s, uint32_t(out_.vertices.size())});
      }
    }
  }
}

// Across an infinitely sharp edge, and around a vertex that sharp edges cut into wedges, each
// side gets its own vertex: the same position (evaluated once), its own normal.
void Stitcher::splitNormals() {
  struct Claim {
    uint32_t vertex;
    int qualifier;
    uint32_t tile;
    uint32_t sidePoint;
    double u, v;
  };
  std::vector<Claim> claims;
  for (const Use& use : uses_) {
    if (use.line.kind != LineKey::kEdge) continue;
    const size_t s = 4 * size_t(use.tile) + use.side;
    const TileFrame frame = frameOf(use.tile);
    for (uint32_t p = out_.sideFirst[s]; p < out_.sideFirst[s + 1]; ++p) {
      const SidePoint& point = out_.sidePoints[p];
      const bool end = p == out_.sideFirst[s] || p + 1 == out_.sideFirst[s + 1];
      if (!end && !seams_.sharp(use.line.a, use.line.b)) continue;
      // Only base vertices and points of sharp edges can split; recompute the exact position.
      const Fraction c = end ? (p == out_.sideFirst[s] ? kZero : kOne) : Fraction{};
      int qualifier = -1;
      Fraction u, v;
      if (end) {
        frame.onSide(use.side, c, u, v);
        if (normalSplitAt(seams_, frame.face, frame.subFace, u, v, qualifier) == NormalSplit::kNone) continue;
      } else {
        qualifier = frame.face;
      }
      const Tile& tile = plan_.tiles[use.tile];
      const double size = tile.size(), at = point.at;
      const double pu = use.side == 0 || use.side == 2 ? (double(tile.ix) + at) * size : (double(tile.ix) + (use.side == 1)) * size;
      const double pv = use.side == 1 || use.side == 3 ? (double(tile.iy) + at) * size : (double(tile.iy) + (use.side == 2)) * size;
      claims.push_back({point.vertex, qualifier, use.tile, p, pu, pv});
    }
  }
  std::sort(claims.begin(), claims.end(), [](const Claim& x, const Claim& y) {
    if (x.vertex != y.vertex) return x.vertex < y.vertex;
    if (x.qualifier != y.qualifier) return x.qualifier < y.qualifier;
    return x.tile < y.tile || (x.tile == y.tile && x.sidePoint < y.sidePoint);
  });
  // The qualifier of the tile that evaluates the vertex keeps it; every other qualifier gets a copy.
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
        out_.vertices.push_back({claims[k].tile, claims[k].u, claims[k].v, original});
      }
      for (size_t g = k; g < groupEnd; ++g) out_.sidePoints[claims[g].sidePoint].vertex = vertex;
      k = groupEnd;
    }
    i = end;
  }
}

Stitching Stitcher::run() {
  collectUses();
  if (checkpoint_) checkpoint_();
  resolveLines();
  numberCorners();
  numberLinePoints();
  if (checkpoint_) checkpoint_();
  buildSides();
  splitNormals();
  return std::move(out_);
}

}  // namespace

Stitching stitchTiles(const AdaptivePlan& plan, const SurfaceTree& tree, const SeamTopology& seams,
                      const std::function<void()>& checkpoint) {
  return Stitcher(plan, tree, seams, checkpoint).run();
}

}  // namespace tessera
