// One thread's scratch while tiles are stitched (core/stitching/tile_stitching.h): the points it names
// before every root and line is counted, the keys it sorts, and the room it keeps from root to
// root, line to line and call to call.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/scratch_pool.h"
#include "core/stitching/line_points.h"
#include "core/stitching/tile_stitching.h"

namespace tessera::stitch {

using line_points::LinePoints;
using line_points::LineUse;

// A vertex reference while roots and lines are stitched: a root's own vertex (root-local id), the
// end of a tile side on the root's boundary (side 4t + k, `end` 0 or 1 in the side's coordinate),
// a seam node (SeamLines' index), or a boundary line's own point (its index among the line's own
// points; the line is the one the side lies on). Named for good in assemble, once every root and
// line is counted.
enum class Ref : uint8_t { kLocal, kSideEnd, kNode, kLineOwn };
struct PendingPoint {
  uint32_t id;
  Ref kind;
  uint8_t end;
  int qualifier;  // normal split for this root (-1: none)
  double at, back;
};

// A tile side on a line inside its root, sorted by line: (axis, fixed coordinate) as one key
// (axis 1: v fixed, sides 0 and 2), then in the order the sides were made (tile, side).
struct InnerKey {
  uint64_t line;
  uint32_t use;
  friend bool operator<(const InnerKey& x, const InnerKey& y) { return x.line < y.line || (x.line == y.line && x.use < y.use); }
  int axis() const { return int(line >> 63); }
  int64_t fixed() const { return int64_t(line & ~(uint64_t(1) << 63)); }
};

// A tile corner strictly inside its root, sorted by position, then tile corner 4 (t − first) + c.
struct InnerCorner {
  int64_t x, y;
  uint32_t tileCorner;
  friend bool operator<(const InnerCorner& a, const InnerCorner& b) {
    return a.x < b.x || (a.x == b.x && (a.y < b.y || (a.y == b.y && a.tileCorner < b.tileCorner)));
  }
};

// What one thread writes while stitching (roots and lines name their slices of it), and the
// room it reuses from root to root and line to line.
struct Arena {
  std::vector<VertexRequest> locals;  // roots' own vertices: inner corners, inner line points, grids
  std::vector<PendingPoint> pool;     // points of tile sides inside roots
  std::vector<LineUse> boundaryUses;  // tile sides on roots' boundaries, root side by root side
  std::vector<PendingPoint> linePool;     // points of tile sides on boundary lines
  std::vector<VertexRequest> ownPoints;  // boundary lines' own points, line by line
  std::vector<InnerCorner> inner;
  std::vector<uint32_t> cornerId;
  std::vector<LineUse> innerUses;
  std::vector<InnerKey> innerKeys;
  std::vector<LineUse> line;
  LinePoints points;
  std::vector<PendingPoint> resolved;
  std::vector<uint32_t> endOf;

  // Every vector emptied, its room kept; returns the bytes held (core/base/scratch_pool.h).
  size_t clearKeepingRoom() {
    size_t bytes = 0;
    auto clear = [&bytes](auto& v) {
      bytes += v.capacity() * sizeof(v[0]);
      v.clear();
    };
    clear(locals), clear(pool), clear(boundaryUses), clear(linePool), clear(ownPoints), clear(inner);
    clear(cornerId), clear(innerUses), clear(innerKeys), clear(line), clear(resolved), clear(endOf);
    clear(points.points), clear(points.lo), clear(points.hi), clear(points.cell), clear(points.order);
    clear(points.byLo), clear(points.stretch), clear(points.merged);
    return bytes;
  }
};

// Arenas kept from call to call (growing fresh arenas every call was ~3 % of the creased torus at
// 1e-3); over 4 MB, one is freed instead.
inline ScratchPool<Arena>& arenaPool() {
  static ScratchPool<Arena> pool(size_t(4) << 20);
  return pool;
}

}  // namespace tessera::stitch
