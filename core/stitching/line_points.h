// A line's points (docs/ADAPTIVE.md §7): the tile sides on one line of the domain, placed in
// exact integer units, and the rule that picks the points they all agree on: every side's
// corners, the own points of sides that keep them, then, densest side first, a side's own points
// wherever the points so far leave a gap wider than its cell. Used by tile_stitching.cpp for the
// lines inside roots and for base edges and spokes alike.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace tessera::line_points {

// Line positions need up to 128 bits in the worst case (deep tiles, many distinct rates on one
// line), but nearly always fit 64, where division is several times cheaper.
using Int = __int128;

inline bool fits64(Int x) { return x == Int(int64_t(x)); }
inline Int quotient(Int a, Int b) { return fits64(a) && fits64(b) ? Int(int64_t(a) / int64_t(b)) : a / b; }
inline long double toLongDouble(Int x) { return fits64(x) ? (long double)int64_t(x) : (long double)x; }

// A tile side on its line. Its own grid point k (0..cells) lies at (a + sign·k) / (cells·2^exp)
// of the line's parameter. A line's positions are integers in units of 1/D, D the least common
// multiple of its sides' denominators, so that everything after is integer arithmetic.
struct LineUse {
  Int a = 0;
  int sign = 1, cells = 1, exp = 0;
  // Its own points at multiples of 1/kept of the side are kept whatever the other sides do (1:
  // its ends only; cells: every one, a side that keeps its own points).
  int kept = 1;
  uint32_t tile = 0;
  uint8_t side = 0;
  int64_t t0 = 0, t1 = 0;  // on a base edge or spoke: its span there, scale kLineScale
};

// A line's points in units of 1/denominator, and each use's span and cell there.
struct LinePoints {
  Int denominator = 1;
  std::vector<Int> points;
  std::vector<Int> lo, hi, cell;  // per use
  std::vector<uint32_t> order;    // the uses by start (byStart), and room for resolveLine
  std::vector<uint32_t> byLo;
  std::vector<Int> stretch, merged;
};

// A line's points, in units of 1/denominator (the least common multiple of its sides' cells).
void resolveLine(const LineUse* uses, size_t count, LinePoints& out);

// The uses of a line in order of where they start (ties in their given order): walked along with
// the sorted points, the first use holding each point is found in one pass.
const std::vector<uint32_t>& byStart(LinePoints& points);

// The first use (in start order from `cursor` on) that holds `value`. (This and the next are
// inline: they run once per point of every line.)
inline size_t holder(const LinePoints& points, const std::vector<uint32_t>& order, size_t& cursor, Int value) {
  while (points.hi[order[cursor]] < value) ++cursor;
  size_t k = cursor;
  while (!(points.lo[order[k]] <= value && value <= points.hi[order[k]])) ++k;
  return order[k];
}

// Coordinate along a use's side, increasing with u or v, and 1 minus it: exact fractions, rounded.
inline void sideCoordinates(const LineUse& use, Int lo, Int hi, Int cell, Int point, double& at, double& back) {
  Int fromLo = point - lo, toHi = hi - point;
  if (use.sign < 0) std::swap(fromLo, toHi);
  const Int span = hi - lo;
  const Int k = quotient(fromLo, cell);
  if (k * cell == fromLo) {
    const int own = int(int64_t(k));  // 0..cells
    at = double(own) / use.cells, back = double(use.cells - own) / use.cells;
    return;
  }
  at = double(toLongDouble(fromLo) / toLongDouble(span));
  back = double(toLongDouble(toHi) / toLongDouble(span));
}

}  // namespace tessera::line_points
