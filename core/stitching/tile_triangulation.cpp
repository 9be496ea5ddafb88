#include "core/stitching/tile_triangulation.h"

#include <algorithm>
#include <bit>

#include "core/base/small_vector.h"
#include "core/stitching/face_triangles.h"

namespace tessera {

namespace {

// A point of a polygon being triangulated: its vertex and its coordinate along the chain it
// lies on (increasing in the chain's direction), and the same measured from the chain's end.
struct ChainPoint {
  uint32_t vertex;
  double at, back;
};
using Chain = SmallVector<ChainPoint, 24>;

// Whether a triangle's face normal points against one of its vertex normals.
bool facesAway(const TriangulationVertices& vertices, uint32_t a, uint32_t b, uint32_t c) {
  const Vec3& pa = vertices.position(a);
  const Vec3 n = cross(vertices.position(b) - pa, vertices.position(c) - pa);
  return dot(n, vertices.normal(a)) < 0 || dot(n, vertices.normal(b)) < 0 || dot(n, vertices.normal(c)) < 0;
}

class TileTriangles {
 public:
  TileTriangles(const TriangulationVertices& vertices, uint32_t gridFirst, TileTriangleOutput& out)
      : vertices_(vertices), gridFirst_(gridFirst), out_(out.indices), away_(out.awayCorners) {}
  uint32_t gridFirst() const { return gridFirst_; }

  void emit(uint32_t a, uint32_t b, uint32_t c) { emit(a, b, c, facesAway(vertices_, a, b, c)); }
  // `away`: facesAway(a, b, c), when the caller has it already.
  void emit(uint32_t a, uint32_t b, uint32_t c, bool away) {
    if (a == b || b == c || a == c) return;
    if (away) flagAwayCorners(a, b, c);
    out_.insert(out_.end(), {a, b, c});
  }
  // A quad a, b, c, d (counter-clockwise) as two triangles: across the diagonal whose triangles
  // face the way their vertex normals do, the shorter one if both (or neither) do.
  // The shorter diagonal's pair is tested first: when it does not flip, it is the choice whatever
  // the other pair does, and the other is not tested (most quads).
  void quad(uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    const bool acShorter = length(vertices_.position(a) - vertices_.position(c)) <=
                           length(vertices_.position(b) - vertices_.position(d));
    bool abc = false, acd = false, abd = false, bcd = false;
    auto testAc = [&] { abc = facesAway(vertices_, a, b, c), acd = facesAway(vertices_, a, c, d); };
    auto testBd = [&] { abd = facesAway(vertices_, a, b, d), bcd = facesAway(vertices_, b, c, d); };
    bool ac;
    if (acShorter) {
      testAc();
      ac = !(abc || acd);
      if (!ac) testBd(), ac = abd || bcd;  // both flip: the shorter
    } else {
      testBd();
      ac = abd || bcd;
      if (ac) testAc(), ac = !(abc || acd);  // both flip: the shorter
    }
    if (ac) {
      emit(a, b, c, abc), emit(a, c, d, acd);
    } else {
      emit(a, b, d, abd), emit(b, c, d, bcd);
    }
  }

  // Triangles from `apex` to every segment of `chain` (which runs counter-clockwise).
  void fan(uint32_t apex, const Chain& chain) {
    for (size_t i = 0; i + 1 < chain.size(); ++i) emit(chain[i].vertex, chain[i + 1].vertex, apex);
  }
  // Two parallel chains with the same direction, `right` of the other seen along it (its
  // segments run counter-clockwise, the other's clockwise); their ends are joined by the zip's
  // first and last rungs.
  void zipParallel(const Chain& right, const Chain& left) {
    size_t i = 0, j = 0;
    while (i + 1 < right.size() || j + 1 < left.size()) {
      const bool advanceRight = j + 1 >= left.size() || (i + 1 < right.size() && right[i + 1].at <= left[j + 1].at);
      if (advanceRight) {
        emit(right[i].vertex, right[i + 1].vertex, left[j].vertex);
        ++i;
      } else {
        emit(right[i].vertex, left[j + 1].vertex, left[j].vertex);
        ++j;
      }
    }
  }
  // Two chains from the ends of a diagonal to a shared corner (the last point of both): `forward`
  // runs counter-clockwise, `backward` clockwise. Neither steps onto the corner before the other
  // has reached the point before it, so no triangle has all its corners on one side.
  void zipToCorner(const Chain& forward, const Chain& backward) {
    size_t i = 0, j = 0;
    const size_t lastF = forward.size() - 1, lastB = backward.size() - 1;
    while (i < lastF || j < lastB) {
      bool advanceForward;
      if (i + 1 == lastF && j + 1 < lastB) {
        advanceForward = false;
      } else if (j + 1 == lastB && i + 1 < lastF) {
        advanceForward = true;
      } else {
        advanceForward = j >= lastB || (i < lastF && forward[i + 1].at <= backward[j + 1].at);
      }
      if (advanceForward) {
        emit(forward[i].vertex, forward[i + 1].vertex, backward[j].vertex);
        ++i;
      } else {
        emit(backward[j + 1].vertex, backward[j].vertex, forward[i].vertex);
        ++j;
      }
      if (i == lastF && j + 1 == lastB) break;  // the last triangle closed both chains
      if (j == lastB && i + 1 == lastF) break;
    }
  }

 private:
  // The corners of a triangle about to be appended that face against its vertex normal.
  void flagAwayCorners(uint32_t a, uint32_t b, uint32_t c) {
    const uint32_t corner[3] = {a, b, c};
    const Vec3& pa = vertices_.position(a);
    const Vec3 n = cross(vertices_.position(b) - pa, vertices_.position(c) - pa);
    for (int k = 0; k < 3; ++k) {
      if (dot(n, vertices_.normal(corner[k])) < 0) away_.push_back(uint32_t(out_.size()) + uint32_t(k));
    }
  }

  const TriangulationVertices& vertices_;
  uint32_t gridFirst_;
  std::vector<uint32_t>& out_;
  std::vector<uint32_t>& away_;
};

Chain reversed(const Chain& chain) {
  Chain out;
  for (size_t i = chain.size(); i-- > 0;) out.push_back({chain[i].vertex, chain[i].back, chain[i].at});
  return out;
}

// A one-cell polygon: four sides counter-clockwise (side k from corner k to corner k + 1), each
// given in counter-clockwise order, coordinates increasing along it. `diagonal` 1 + d keeps
// diagonal d (0: corners 0–2, 1: corners 1–3) as an edge (Tile::diagonal); 0 leaves it free.
void triangulateCell(const Chain sides[4], TileTriangles& out, int diagonal = 0) {
  bool extra[4];
  int count = 0;
  for (int k = 0; k < 4; ++k) count += extra[k] = sides[k].size() > 2;
  auto corner = [&](int k) { return sides[k % 4].front().vertex; };
  // A half: the diagonal from corner `first` to corner first + 2 and the two sides between,
  // fanned from the diagonal's far end when one side has no extras, else zipped.
  auto half = [&](int first) {
    const int second = (first + 1) % 4;
    const Chain& a = sides[first];
    const Chain& b = sides[second];
    if (!extra[second]) return out.fan(b.back().vertex, a);
    if (!extra[first]) return out.fan(a.front().vertex, b);
    out.zipToCorner(a, reversed(b));
  };
  if (diagonal > 0) {
    half(diagonal - 1);
    half(diagonal + 1);
    return;
  }
  if (count == 0) return out.quad(corner(0), corner(1), corner(2), corner(3));
  for (int k = 0; k < 4; ++k) {
    // One side, or two sides meeting at corner k + 1: a fan from a corner on neither.
    const bool one = count == 1 && extra[k];
    const bool adjacent = count == 2 && extra[k] && extra[(k + 1) % 4];
    if (!one && !adjacent) continue;
    const int apex = one ? k + 2 : k + 3;
    for (int s = 0; s < 4; ++s) {
      if (s != apex % 4 && s != (apex + 3) % 4) out.fan(corner(apex), sides[s]);
    }
    return;
  }
  if (count == 2) {
    // Opposite sides: zip them; sides 0 and 2 run along u, 1 and 3 along v.
    const int k = extra[0] ? 0 : 1;
    return out.zipParallel(sides[k], reversed(sides[k + 2]));
  }
  // Three or four sides: split along the diagonal from corner 0 to corner 2.
  half(0);
  half(2);
}

// The anchored zip of one side (docs/ADAPTIVE.md §5): `boundary` from the side's start corner to
// its end corner, `row` the inner grid's border row along it (ru − 1 points at i/ru), both
// counter-clockwise around the tile and coordinates increasing.
void anchoredZip(const Chain& boundary, const Chain& row, TileTriangles& out) {
  const size_t cells = row.size() + 1;
  // Anchor of row interval c: the side point in [c/n, (c+1)/n] nearest its middle; the end
  // intervals are anchored at the corners.
  SmallVector<size_t, 24> anchor;
  for (size_t c = 0; c < cells; ++c) anchor.push_back(0);
  anchor[cells - 1] = boundary.size() - 1;
  size_t p = 0;
  for (size_t c = 1; c + 1 < cells; ++c) {
    const double lo = row[c - 1].at, hi = row[c].at, middle = (lo + hi) / 2;
    while (p + 1 < boundary.size() && boundary[p].at < lo) ++p;
    size_t best = p;
    for (size_t q = p; q < boundary.size() && boundary[q].at <= hi; ++q) {
      if (std::abs(boundary[q].at - middle) < std::abs(boundary[best].at - middle)) best = q;
    }
    anchor[c] = best;
    out.emit(boundary[best].vertex, row[c].vertex, row[c - 1].vertex);
  }
  // Side segments between anchors c and c + 1 fan to row point c (the one between them).
  for (size_t c = 0; c + 1 < cells; ++c) {
    for (size_t q = anchor[c]; q < anchor[c + 1]; ++q) out.emit(boundary[q].vertex, boundary[q + 1].vertex, row[c].vertex);
  }
}

Chain sideChain(const Stitching& stitching, size_t t, int k) {
  size_t count;
  const SidePoint* points = stitching.side(t, k, count);
  Chain chain;
  for (size_t i = 0; i < count; ++i) chain.push_back({points[i].vertex, points[i].at, points[i].back});
  return chain;
}

// Sides as stored run along increasing u or v; sides 2 and 3 run the other way around the tile.
void counterClockwiseSides(const Stitching& stitching, size_t t, Chain sides[4]) {
  for (int k = 0; k < 4; ++k) {
    sides[k] = sideChain(stitching, t, k);
    if (k >= 2) sides[k] = reversed(sides[k]);
  }
}

void gridTile(const Stitching& stitching, size_t t, const Tile& tile, TileTriangles& out) {
  const int ru = tile.ru, rv = tile.rv;
  auto grid = [&](int i, int j) { return out.gridFirst() + uint32_t((j - 1) * (ru - 1) + (i - 1)); };
  for (int j = 1; j + 1 < rv; ++j) {
    for (int i = 1; i + 1 < ru; ++i) out.quad(grid(i, j), grid(i + 1, j), grid(i + 1, j + 1), grid(i, j + 1));
  }
  Chain sides[4];
  counterClockwiseSides(stitching, t, sides);
  // Each side's border row, counter-clockwise, at coordinates along the side.
  Chain rows[4];
  for (int i = 1; i < ru; ++i) {
    const double at = double(i) / ru, back = double(ru - i) / ru;
    rows[0].push_back({grid(i, 1), at, back});
    rows[2].push_back({grid(ru - i, rv - 1), at, back});
  }
  for (int j = 1; j < rv; ++j) {
    const double at = double(j) / rv, back = double(rv - j) / rv;
    rows[1].push_back({grid(ru - 1, j), at, back});
    rows[3].push_back({grid(1, rv - j), at, back});
  }
  for (int k = 0; k < 4; ++k) anchoredZip(sides[k], rows[k], out);
}

// A one-cell-wide strip: its long sides hold their own grid points (tile_stitching.h), so it is
// a column (or row) of one-cell polygons.
void stripTile(const Stitching& stitching, size_t t, const Tile& tile, TileTriangles& out) {
  const bool alongV = tile.ru == 1;
  const int cells = alongV ? tile.rv : tile.ru;
  // Long sides in increasing coordinate: along v sides 1 (u = 1) and 3 (u = 0); else 0 and 2.
  const Chain longA = sideChain(stitching, t, alongV ? 1 : 0), longB = sideChain(stitching, t, alongV ? 3 : 2);
  const Chain shortLow = sideChain(stitching, t, alongV ? 0 : 3), shortHigh = sideChain(stitching, t, alongV ? 2 : 1);
  size_t a = 0, b = 0;
  for (int c = 0; c < cells; ++c) {
    // The long sides hold the exact points c/cells: the nearest doubles compare equal.
    const double hi = double(c + 1) / cells;
    Chain pieceA{longA[a]}, pieceB{longB[b]};
    while (longA[a].at < hi) pieceA.push_back(longA[++a]);
    while (longB[b].at < hi) pieceB.push_back(longB[++b]);
    // Cuts between cells run across the strip: along u from side 3 to side 1 (a column), along
    // v from side 0 to side 2 (a row).
    auto cut = [alongV](const ChainPoint& onA, const ChainPoint& onB) {
      return alongV ? Chain{{onB.vertex, 0, 1}, {onA.vertex, 1, 0}} : Chain{{onA.vertex, 0, 1}, {onB.vertex, 1, 0}};
    };
    const Chain low = c == 0 ? shortLow : cut(pieceA.front(), pieceB.front());
    const Chain high = c + 1 == cells ? shortHigh : cut(pieceA.back(), pieceB.back());
    Chain sides[4];
    if (alongV) {
      // Counter-clockwise: bottom (u increasing), right (v increasing), top and left reversed.
      sides[0] = low, sides[1] = pieceA, sides[2] = reversed(high), sides[3] = reversed(pieceB);
    } else {
      // Along u: long side A is v = 0 (u increasing), B is v = 1; short sides are u = 0 and u = 1.
      sides[0] = pieceA, sides[1] = high, sides[2] = reversed(pieceB), sides[3] = reversed(low);
    }
    triangulateCell(sides, out);
  }
}

// A cell-wise tile (adaptive_plan.h): its sides hold their own points exactly (c/ru along u,
// c/rv along v), so each cell is the polygon of its corners (inner grid points or side points)
// and the side points between them, triangulated as the one-cell tile it was; chains in cell
// coordinates.
void cellwiseTile(const Stitching& stitching, size_t t, const Tile& tile, TileTriangles& out) {
  const int ru = tile.ru, rv = tile.rv;
  Chain sides[4];
  SmallVector<size_t, 65> start[4];  // start[k][c]: the index of point c/cells on side k
  for (int k = 0; k < 4; ++k) {
    sides[k] = sideChain(stitching, t, k);
    const int cells = k == 0 || k == 2 ? ru : rv;
    size_t p = 0;
    for (int c = 0; c <= cells; ++c) {
      const double at = double(c) / cells;
      while (p + 1 < sides[k].size() && sides[k][p].at < at) ++p;
      start[k].push_back(p);
    }
  }
  auto grid = [&](int i, int j) { return out.gridFirst() + uint32_t((j - 1) * (ru - 1) + (i - 1)); };
  auto lattice = [&](int i, int j) -> uint32_t {
    if (j == 0) return sides[0][start[0][i]].vertex;
    if (j == rv) return sides[2][start[2][i]].vertex;
    if (i == 0) return sides[3][start[3][j]].vertex;
    if (i == ru) return sides[1][start[1][j]].vertex;
    return grid(i, j);
  };
  // Side k's points over cell c, increasing, with coordinates along the cell.
  auto piece = [&](int k, int c) {
    const int cells = k == 0 || k == 2 ? ru : rv;
    Chain chain;
    for (size_t p = start[k][c]; p <= start[k][c + 1]; ++p) {
      const ChainPoint& q = sides[k][p];
      chain.push_back({q.vertex, q.at * cells - c, q.back * cells - (cells - 1 - c)});
    }
    return chain;
  };
  auto segment = [](uint32_t a, uint32_t b) { return Chain{{a, 0, 1}, {b, 1, 0}}; };
  // Whether side k's piece over cell c holds only the cell's corners.
  auto bare = [&](int k, int c) { return start[k][c + 1] - start[k][c] == 1; };
  for (int j = 0; j < rv; ++j) {
    for (int i = 0; i < ru; ++i) {
      if ((j > 0 || bare(0, i)) && (i + 1 < ru || bare(1, j)) && (j + 1 < rv || bare(2, i)) && (i > 0 || bare(3, j))) {
        // No points but its corners (every inner cell): triangulateCell's quad, or its two halves
        // along the diagonal the cell keeps, without building the chains.
        const uint32_t c[4] = {lattice(i, j), lattice(i + 1, j), lattice(i + 1, j + 1), lattice(i, j + 1)};
        const int diagonal = tile.cellDiagonal(i, j);
        if (diagonal == 0) {
          out.quad(c[0], c[1], c[2], c[3]);
        } else {
          const int d = diagonal - 1;
          out.emit(c[d], c[d + 1], c[d + 2]);
          out.emit(c[d + 2], c[(d + 3) % 4], c[d]);
        }
        continue;
      }
      Chain cell[4];
      cell[0] = j == 0 ? piece(0, i) : segment(lattice(i, j), lattice(i + 1, j));
      cell[1] = i + 1 == ru ? piece(1, j) : segment(lattice(i + 1, j), lattice(i + 1, j + 1));
      cell[2] = reversed(j + 1 == rv ? piece(2, i) : segment(lattice(i, j + 1), lattice(i + 1, j + 1)));
      cell[3] = reversed(i == 0 ? piece(3, j) : segment(lattice(i, j), lattice(i, j + 1)));
      triangulateCell(cell, out, tile.cellDiagonal(i, j));
    }
  }
}

// A triangular face as one triangle (core/stitching/face_triangles.h), split at the middles its edges kept:
// sub-face k's tile t + k holds the face's edge k as its side 0, from corner k (its first point)
// through the middle, if kept, to corner k + 1. Sub-face 0's tile emits the triangles.
void faceTriangle(const Stitching& stitching, size_t t, const Tile& tile, TileTriangles& out) {
  if (tile.faceTriangle != 1) return;
  const FaceTrianglePoints face = faceTrianglePoints(stitching, t);
  const uint32_t *corner = face.corner, *middle = face.middle;
  const int middles = face.middles;
  if (middles == 0) return out.emit(corner[0], corner[1], corner[2]);
  if (middles == 7) {
    for (int k = 0; k < 3; ++k) out.emit(corner[k], middle[k], middle[(k + 2) % 3]);
    return out.emit(middle[0], middle[1], middle[2]);
  }
  // One middle, on edge j: the fold from it to the opposite corner.
  const int j = std::countr_zero(unsigned(middles));
  out.emit(corner[j], middle[j], corner[(j + 2) % 3]);
  out.emit(middle[j], corner[(j + 1) % 3], corner[(j + 2) % 3]);
}

}  // namespace


void triangulateTile(const Stitching& stitching, size_t t, const Tile& tile, uint32_t gridFirst,
                     const TriangulationVertices& vertices, TileTriangleOutput& output) {
  TileTriangles out(vertices, gridFirst, output);
  if (tile.faceTriangle) return faceTriangle(stitching, t, tile, out);
  if (tile.cellwise) return cellwiseTile(stitching, t, tile, out);
  if (tile.ru >= 2 && tile.rv >= 2) return gridTile(stitching, t, tile, out);
  if (tile.ru == 1 && tile.rv == 1) {
    Chain sides[4];
    counterClockwiseSides(stitching, t, sides);
    return triangulateCell(sides, out, tile.diagonal);
  }
  stripTile(stitching, t, tile, out);
}

}  // namespace tessera
