#include "core/uniform/watertight_tessellator.h"

#include <tbb/concurrent_unordered_map.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>

#include "core/math/bicubic.h"

namespace tessera {

namespace {

// Piece sides, counter-clockwise: t=0 (s: 0→1), s=1 (t: 0→1), t=1 (s: 1→0), s=0 (t: 1→0).
void sidePoint(int side, double phi, double& s, double& t) {
  switch (side) {
    case 0: s = phi, t = 0; break;
    case 1: s = 1, t = phi; break;
    case 2: s = 1 - phi, t = 1; break;
    default: s = 0, t = 1 - phi; break;
  }
}

// One side of one piece on its canonical line.
struct SideUse {
  DomainKey line;
  double from, to;  // line parameters at the side's start and end
  uint32_t piece;
  int side;
};

// A canonical line: its uses are a run of the sorted uses, in plan order. Its sorted breaks (the
// parameters where some side starts or ends) and, per elementary interval between them, the level,
// the use whose piece evaluates it (or -1) and the first of its level − 1 interior vertices
// (numbered consecutively) live in flat arrays from 2·firstUse on: a line has at most two breaks
// per use.
struct Line {
  uint32_t firstUse = 0, useCount = 0, breakCount = 0;
};

// Consistent with DomainKey's == (0.0 and -0.0 hash alike); every part mixed (splitmix64), since
// the map's buckets take the low bits.
struct DomainKeyHash {
  static uint64_t mix(uint64_t z) {
    z += 0x9e3779b97f4a7c15u;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return z ^ (z >> 31);
  }
  static uint64_t bits(double value) {
    uint64_t b;
    const double canonical = value == 0 ? 0.0 : value;
    std::memcpy(&b, &canonical, sizeof b);
    return b;
  }
  size_t operator()(const DomainKey& k) const {
    uint64_t h = mix(uint64_t(k.kind) << 32 ^ uint32_t(k.a));
    h = mix(h ^ (uint64_t(uint32_t(k.b)) << 32 | uint32_t(k.c)));
    h = mix(h ^ bits(k.x));
    return size_t(mix(h ^ bits(k.y)));
  }
};

constexpr uint32_t kNoVertex = UINT32_MAX;

// A point of the domain where piece sides end: the first piece (in plan order) that has it
// evaluates it, whichever thread found it first.
struct PointEntry {
  std::atomic<uint32_t> owner{kNoVertex};
  uint32_t vertex = kNoVertex;
};

// Triangles of a run of pieces, in piece order; runs are concatenated in order.
struct TriangleBatch {
  std::vector<uint32_t> indices, pieces;
  std::vector<double> st;
};

// Passes that give the same mesh whatever the thread count (the mesh a one-pass walk in plan
// order gives): lines are collected in plan order and resolved on all cores; the points where
// piece sides end are found on all cores, each owned by the first piece that has it; vertices are
// numbered on one thread in plan order (no lookups left by then); triangles are emitted on all
// cores, run by run, and concatenated in order; vertices are evaluated last, on all cores.
class Tessellator {
 public:
  Tessellator(const TessellationPlan& plan, const FaceTopology& faces, bool recordParameters,
              const std::function<void()>& checkpoint)
      : plan_(plan), faces_(faces), recordParameters_(recordParameters), checkpoint_(checkpoint) {}
  TriangleMesh run();

 private:
  struct Corner {
    uint32_t vertex;
    double phi, s, t;  // position along a side (boundary corners), and in the piece
  };
  void collectSides();
  void resolveLines();
  void numberLineVertices(const Line& line);
  uint32_t vertexAt(uint32_t piece, double s, double t);
  struct LocalPoint {
    PointEntry* entry;
    double s, t;
  };
  // What the point pass found for a run of pieces: every side-end visit, in visit order, and each
  // piece's distinct points in first-visit order.
  struct PieceRun {
    std::vector<PointEntry*> visits;
    std::vector<LocalPoint> points;
    std::vector<uint32_t> visitFirst, pointFirst;  // per piece of the run, and the end
  };
  static constexpr size_t kRun = 512;
  void findPoints(size_t run);
  void numberPieces();
  template <typename PointIndex>
  void sideVertices(uint32_t piece, int side, PointIndex&& pointIndex,
                    std::vector<Corner>& result) const;
  using Sides = std::array<std::vector<Corner>, 4>;
  void triangulatePiece(uint32_t piece, PointEntry* const* visits, Sides& sides,
                        TriangleBatch& out) const;
  void emitTriangle(const Corner& a, const Corner& b, const Corner& c, uint32_t piece,
                    TriangleBatch& out) const;
  void triangulateAll();
  void evaluateVertices();

  const TessellationPlan& plan_;
  const FaceTopology& faces_;
  const bool recordParameters_;
  const std::function<void()>& checkpoint_;
  std::vector<SideUse> uses_;          // sorted by line, then plan order
  std::vector<uint32_t> sideUse_;      // piece side 4p + k → its use
  std::vector<uint32_t> useLine_;      // use → its line
  std::vector<Line> lines_;            // in key order
  std::vector<double> breaks_;
  std::vector<int> levels_, owners_;
  std::vector<uint32_t> interiorFirst_;
  tbb::concurrent_unordered_map<DomainKey, PointEntry, DomainKeyHash> points_;
  std::vector<PieceRun> runs_;
  std::vector<uint8_t> trianglePair_;  // level 1 and nothing on its sides but its corners
  std::vector<uint32_t> gridFirst_;    // first of its (N−1)² (or one centre) inner vertices
  struct VertexRequest {
    uint32_t piece;
    double s, t;
  };
  std::vector<VertexRequest> requests_;  // vertex i is piece requests_[i].piece at (s, t)
  TriangleMesh mesh_;
};

// Every piece side's line and parameters on all cores, then the sides sorted by line (ties in plan
// order), so that lines come in key order and each line's uses in plan order.
void Tessellator::collectSides() {
  const size_t pieces = plan_.pieces.size();
  uses_.resize(4 * pieces);
  tbb::parallel_for(size_t(0), pieces, [&](size_t piece) {
    const uint32_t p = uint32_t(piece);
    const PatchDomain& d = plan_.pieces[p].domain;
    for (int side = 0; side < 4; ++side) {
      double s0, t0, s1, t1, u0, v0, u1, v1;
      sidePoint(side, 0, s0, t0);
      sidePoint(side, 1, s1, t1);
      d.map(s0, t0, u0, v0);
      d.map(s1, t1, u1, v1);
      bool alongU = v0 == v1;
      SideUse& use = uses_[4 * piece + side];
      use.line = lineKey(faces_, d.baseFace, d.subFace, u0, v0, alongU, use.from);
      lineKey(faces_, d.baseFace, d.subFace, u1, v1, alongU, use.to);
      use.piece = p;
      use.side = side;
    }
  });
  tbb::parallel_sort(uses_.begin(), uses_.end(), [](const SideUse& a, const SideUse& b) {
    if (a.line < b.line) return true;
    if (b.line < a.line) return false;
    return a.piece < b.piece || (a.piece == b.piece && a.side < b.side);
  });
  sideUse_.resize(uses_.size());
  useLine_.resize(uses_.size());
  lines_.clear();
  for (uint32_t u = 0; u < uses_.size(); ++u) {
    if (u == 0 || !(uses_[u].line == uses_[u - 1].line)) lines_.push_back({u, 0, 0});
    ++lines_.back().useCount;
    useLine_[u] = uint32_t(lines_.size() - 1);
    sideUse_[4 * size_t(uses_[u].piece) + uses_[u].side] = u;
  }
}

// Elementary intervals between all side ends on a line; each takes the finest level any side
// covering it needs (its level scaled to the interval's share of the side). Lines are independent
// and resolved on all cores; their vertices are numbered in key order afterwards.
void Tessellator::resolveLines() {
  breaks_.resize(2 * uses_.size());
  levels_.resize(2 * uses_.size());
  owners_.resize(2 * uses_.size());
  interiorFirst_.resize(2 * uses_.size());
  tbb::parallel_for(size_t(0), lines_.size(), [&](size_t l) {
    Line& line = lines_[l];
    const SideUse* uses = uses_.data() + line.firstUse;
    double* breaks = breaks_.data() + 2 * size_t(line.firstUse);
    for (uint32_t u = 0; u < line.useCount; ++u) {
      breaks[2 * u] = uses[u].from;
      breaks[2 * u + 1] = uses[u].to;
    }
    std::sort(breaks, breaks + 2 * line.useCount);
    line.breakCount = uint32_t(std::unique(breaks, breaks + 2 * line.useCount) - breaks);
    const uint32_t intervals = line.breakCount - 1;
    int* levels = levels_.data() + 2 * size_t(line.firstUse);
    int* owners = owners_.data() + 2 * size_t(line.firstUse);
    std::fill(levels, levels + intervals, 1);
    std::fill(owners, owners + intervals, -1);
    for (uint32_t u = 0; u < line.useCount; ++u) {
      const SideUse& use = uses[u];
      double lo = std::min(use.from, use.to), hi = std::max(use.from, use.to);
      int level = plan_.pieces[use.piece].level;
      for (uint32_t i = 0; i < intervals; ++i) {
        if (breaks[i] < lo || breaks[i + 1] > hi) continue;
        double share = (breaks[i + 1] - breaks[i]) / (hi - lo);
        levels[i] = std::max(levels[i], int(std::ceil(level * share - 1e-9)));
        if (owners[i] < 0) owners[i] = int(u);
      }
    }
  });
  for (const Line& line : lines_) numberLineVertices(line);
}

void Tessellator::numberLineVertices(const Line& line) {
  const size_t first = 2 * size_t(line.firstUse);
  const double* breaks = breaks_.data() + first;
  for (uint32_t i = 0; i + 1 < line.breakCount; ++i) {
    if (owners_[first + i] < 0) continue;
    const SideUse& use = uses_[line.firstUse + owners_[first + i]];
    const int level = levels_[first + i];
    for (int k = 1; k < level; ++k) {
      double parameter = breaks[i] + (breaks[i + 1] - breaks[i]) * k / level;
      double s, t;
      sidePoint(use.side, (parameter - use.from) / (use.to - use.from), s, t);
      const uint32_t vertex = vertexAt(use.piece, s, t);
      if (k == 1) interiorFirst_[first + i] = vertex;
    }
  }
}

uint32_t Tessellator::vertexAt(uint32_t p, double s, double t) {
  requests_.push_back({p, s, t});
  return uint32_t(requests_.size() - 1);
}

// The vertices along one side, start corner to end corner, with their position phi on the side,
// into `result` (the caller's, reused). `pointIndex(s, t)` gives the vertex of each interval
// end, in the order they are visited.
template <typename PointIndex>
void Tessellator::sideVertices(uint32_t p, int side, PointIndex&& pointIndex,
                               std::vector<Corner>& result) const {
  const uint32_t u = sideUse_[4 * size_t(p) + side];
  const SideUse& use = uses_[u];
  const Line& line = lines_[useLine_[u]];
  const size_t first = 2 * size_t(line.firstUse);
  const double* breaks = breaks_.data() + first;
  const int* levels = levels_.data() + first;
  result.clear();
  double lo = std::min(use.from, use.to), hi = std::max(use.from, use.to);
  auto corner = [&](uint32_t vertex, double parameter) {
    Corner c{vertex, (parameter - use.from) / (use.to - use.from), 0, 0};
    sidePoint(side, c.phi, c.s, c.t);
    return c;
  };
  // Breaks are sorted: the side's intervals start at lo (a line can carry thousands of them).
  const size_t count = line.breakCount;
  for (size_t i = size_t(std::lower_bound(breaks, breaks + count, lo) - breaks);
       i + 1 < count && breaks[i + 1] <= hi; ++i) {
    Corner start = corner(0, breaks[i]);
    start.vertex = pointIndex(start.s, start.t);
    result.push_back(start);
    for (int k = 1; k < levels[i]; ++k) {
      double parameter = breaks[i] + (breaks[i + 1] - breaks[i]) * k / levels[i];
      result.push_back(corner(interiorFirst_[first + i] + uint32_t(k - 1), parameter));
    }
  }
  Corner end = corner(0, hi);
  end.vertex = pointIndex(end.s, end.t);
  result.push_back(end);
  if (use.from > use.to) std::reverse(result.begin(), result.end());  // side runs against the line
}

// A piece's inner grid: (N−1)² points at (i/N, j/N), i, j = 1 … N−1; with N = 1 one centre point.
int innerSide(int level) { return std::max(level - 1, 1); }
double gridStep(int level) { return level == 1 ? 0.5 : 1.0 / level; }

// Pieces of one run, on any thread: the domain points their sides end at, each registered in
// points_ with the smallest piece that has it as owner.
void Tessellator::findPoints(size_t r) {
  PieceRun& run = runs_[r];
  std::vector<Corner> side;
  const size_t end = std::min(plan_.pieces.size(), (r + 1) * kRun);
  for (size_t piece = r * kRun; piece < end; ++piece) {
    const uint32_t p = uint32_t(piece);
    const PatchDomain& d = plan_.pieces[p].domain;
    const size_t firstPoint = run.points.size();
    run.visitFirst.push_back(uint32_t(run.visits.size()));
    run.pointFirst.push_back(uint32_t(firstPoint));
    auto visit = [&](double s, double t) {
      // Each corner ends one side and starts the next: found once per piece.
      for (size_t k = firstPoint; k < run.points.size(); ++k) {
        if (run.points[k].s == s && run.points[k].t == t) {
          run.visits.push_back(run.points[k].entry);
          return kNoVertex;
        }
      }
      double u, v;
      d.map(s, t, u, v);
      PointEntry& entry = points_[pointKey(faces_, d.baseFace, d.subFace, u, v)];
      uint32_t owner = entry.owner.load(std::memory_order_relaxed);
      while (p < owner && !entry.owner.compare_exchange_weak(owner, p)) {
      }
      run.points.push_back({&entry, s, t});
      run.visits.push_back(&entry);
      return kNoVertex;
    };
    bool onlyCorners = true;
    for (int k = 0; k < 4; ++k) {
      sideVertices(p, k, visit, side);
      onlyCorners &= side.size() == 2;
    }
    trianglePair_[p] = plan_.pieces[p].level == 1 && onlyCorners;
  }
  run.visitFirst.push_back(uint32_t(run.visits.size()));
  run.pointFirst.push_back(uint32_t(run.points.size()));
}

// Vertex numbers in plan order, as a one-pass tessellator gives them: each piece's new points (those
// it owns, in first-visit order), then its inner grid.
void Tessellator::numberPieces() {
  for (size_t r = 0; r < runs_.size(); ++r) {
    const PieceRun& run = runs_[r];
    for (size_t k = 0; k + 1 < run.pointFirst.size(); ++k) {
      const uint32_t p = uint32_t(r * kRun + k);
      if (checkpoint_ && p % 4096 == 0) checkpoint_();
      for (uint32_t q = run.pointFirst[k]; q < run.pointFirst[k + 1]; ++q) {
        const LocalPoint& point = run.points[q];
        if (point.entry->owner.load(std::memory_order_relaxed) == p &&
            point.entry->vertex == kNoVertex) {
          point.entry->vertex = vertexAt(p, point.s, point.t);
        }
      }
      gridFirst_[p] = uint32_t(requests_.size());
      if (trianglePair_[p]) continue;
      const int level = plan_.pieces[p].level, inner = innerSide(level);
      const double step = gridStep(level);
      for (int j = 0; j < inner; ++j) {
        for (int i = 0; i < inner; ++i) vertexAt(p, (i + 1) * step, (j + 1) * step);
      }
    }
  }
}

void Tessellator::emitTriangle(const Corner& a, const Corner& b, const Corner& c, uint32_t piece,
                               TriangleBatch& out) const {
  if (a.vertex == b.vertex || b.vertex == c.vertex || a.vertex == c.vertex) return;
  out.indices.insert(out.indices.end(), {a.vertex, b.vertex, c.vertex});
  out.pieces.push_back(piece);
  if (recordParameters_) out.st.insert(out.st.end(), {a.s, a.t, b.s, b.t, c.s, c.t});
}

void Tessellator::triangulatePiece(uint32_t p, PointEntry* const* visits, Sides& sides,
                                   TriangleBatch& out) const {
  const int n = plan_.pieces[p].level;
  for (int side = 0; side < 4; ++side)
    sideVertices(p, side, [&](double, double) { return (*visits++)->vertex; }, sides[side]);
  if (trianglePair_[p]) {
    emitTriangle(sides[0][0], sides[0][1], sides[1][1], p, out);
    emitTriangle(sides[0][0], sides[1][1], sides[2][1], p, out);
    return;
  }
  const int inner = innerSide(n);
  const double step = gridStep(n);
  auto at = [&](int i, int j) {
    return Corner{gridFirst_[p] + uint32_t(j * inner + i), 0, (i + 1) * step, (j + 1) * step};
  };
  for (int j = 0; j + 1 < inner; ++j) {
    for (int i = 0; i + 1 < inner; ++i) {
      emitTriangle(at(i, j), at(i + 1, j), at(i + 1, j + 1), p, out);
      emitTriangle(at(i, j), at(i + 1, j + 1), at(i, j + 1), p, out);
    }
  }
  // Each side's boundary polyline zipped to the inner grid's border row, both running with the side.
  for (int side = 0; side < 4; ++side) {
    std::vector<Corner> row;
    for (int k = 0; k < inner; ++k) {
      int i = 0, j = 0;
      switch (side) {
        case 0: i = k, j = 0; break;
        case 1: i = inner - 1, j = k; break;
        case 2: i = inner - 1 - k, j = inner - 1; break;
        default: i = 0, j = inner - 1 - k; break;
      }
      Corner c = at(i, j);
      c.phi = (k + 1) * step;
      row.push_back(c);
    }
    const auto& boundary = sides[side];
    size_t a = 0, c = 0;
    while (a + 1 < boundary.size() || c + 1 < row.size()) {
      bool advanceBoundary =
          c + 1 >= row.size() || (a + 1 < boundary.size() && boundary[a + 1].phi <= row[c + 1].phi);
      if (advanceBoundary) {
        emitTriangle(boundary[a], boundary[a + 1], row[c], p, out);
        ++a;
      } else {
        emitTriangle(boundary[a], row[c + 1], row[c], p, out);
        ++c;
      }
    }
  }
}

// The runs on all cores, each into its own batch, then the batches in order.
void Tessellator::triangulateAll() {
  std::vector<TriangleBatch> batches(runs_.size());
  tbb::parallel_for(size_t(0), runs_.size(), [&](size_t r) {
    if (checkpoint_) checkpoint_();
    const PieceRun& run = runs_[r];
    Sides sides;
    for (size_t k = 0; k + 1 < run.visitFirst.size(); ++k) {
      triangulatePiece(uint32_t(r * kRun + k), run.visits.data() + run.visitFirst[k], sides,
                       batches[r]);
    }
  });
  // Appended on one thread, into room made once (grown by doubling, the copies took half a
  // second for armorguy at level 16, 4.4 M triangles); each batch freed once copied and the
  // checkpoint reached between them.
  size_t indices = 0, st = 0;
  for (const TriangleBatch& batch : batches) indices += batch.indices.size(), st += batch.st.size();
  mesh_.indices.reserve(indices);
  mesh_.trianglePiece.reserve(indices / 3);
  mesh_.triangleST.reserve(st);
  for (TriangleBatch& batch : batches) {
    if (checkpoint_) checkpoint_();
    mesh_.indices.insert(mesh_.indices.end(), batch.indices.begin(), batch.indices.end());
    mesh_.trianglePiece.insert(mesh_.trianglePiece.end(), batch.pieces.begin(), batch.pieces.end());
    mesh_.triangleST.insert(mesh_.triangleST.end(), batch.st.begin(), batch.st.end());
    batch = TriangleBatch();
  }
}

void Tessellator::evaluateVertices() {
  const size_t count = requests_.size();
  mesh_.positions.resize(count);
  mesh_.normals.resize(count);
  mesh_.vertexFace.resize(count);
  mesh_.vertexSubFace.resize(count);
  mesh_.vertexUv.resize(2 * count);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1024), [&](const auto& range) {
    if (checkpoint_) checkpoint_();
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const auto [p, s, t] = requests_[i];
      const BezierPiece& piece = plan_.pieces[p];
      PatchSample sample = evaluateBezier(piece.bezier.data(), s, t);
      Vec3d normal = cross(sample.dPds, sample.dPdt);
      if (piece.kind == PieceKind::kInnermost && s == 0 && t == 0 &&
          length(plan_.evNormals[piece.ring]) > 0) {
        normal = plan_.evNormals[piece.ring];
      }
      double l = length(normal);
      normal = l > 0 ? normal * (1.0 / l) : Vec3d(0, 0, 1);
      mesh_.positions[i] = Vec3(sample.position);
      mesh_.normals[i] = Vec3(normal);
      mesh_.vertexFace[i] = piece.domain.baseFace;
      mesh_.vertexSubFace[i] = piece.domain.subFace;
      piece.domain.map(s, t, mesh_.vertexUv[2 * i], mesh_.vertexUv[2 * i + 1]);
    }
  });
}

TriangleMesh Tessellator::run() {
  collectSides();
  if (checkpoint_) checkpoint_();
  resolveLines();
  if (checkpoint_) checkpoint_();
  const size_t pieces = plan_.pieces.size();
  runs_.resize((pieces + kRun - 1) / kRun);
  trianglePair_.resize(pieces);
  gridFirst_.resize(pieces);
  // Buckets for the points up front (about one per piece on a quad mesh): a split-ordered list
  // that grows its buckets as it fills walks long chains.
  points_.rehash(2 * pieces);
  tbb::parallel_for(size_t(0), runs_.size(), [&](size_t r) {
    if (checkpoint_) checkpoint_();
    findPoints(r);
  });
  numberPieces();
  triangulateAll();
  evaluateVertices();
  return std::move(mesh_);
}

}  // namespace

int64_t estimateTriangles(const TessellationPlan& plan) {
  int64_t total = 0;
  for (const BezierPiece& piece : plan.pieces) total += 2 * int64_t(piece.level) * piece.level + 4;
  return total;
}

TriangleMesh tessellatePlan(const TessellationPlan& plan, const FaceTopology& faces, bool recordParameters,
                           const std::function<void()>& checkpoint) {
  return Tessellator(plan, faces, recordParameters, checkpoint).run();
}

}  // namespace tessera
