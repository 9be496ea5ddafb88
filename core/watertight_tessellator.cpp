#include "core/watertight_tessellator.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include "core/bicubic.h"

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

struct SideUse {
  uint32_t piece;
  int side;
  double from, to;  // line parameters at the side's start and end
};

struct Line {
  std::vector<SideUse> uses;
  std::vector<double> breaks;          // sorted parameters where some side starts or ends
  std::vector<int> levels;             // per elementary interval
  std::vector<std::vector<uint32_t>> interiorVertices;  // per interval, in increasing parameter
};

class Tessellator {
 public:
  Tessellator(const TessellationPlan& plan, const FaceTopology& faces, bool recordParameters,
              const std::function<void()>& checkpoint)
      : plan_(plan), faces_(faces), recordParameters_(recordParameters), checkpoint_(checkpoint) {}
  TriangleMesh run();

 private:
  void collectSides();
  void resolveLines();
  uint32_t vertexAt(uint32_t piece, double s, double t);
  uint32_t pointVertex(uint32_t piece, double s, double t);
  struct Corner {
    uint32_t vertex;
    double phi, s, t;  // position along a side (boundary corners), and in the piece
  };
  std::vector<Corner> sideVertices(uint32_t piece, int side);
  void triangulatePiece(uint32_t piece);
  void emitTriangle(const Corner& a, const Corner& b, const Corner& c, uint32_t piece);

  const TessellationPlan& plan_;
  const FaceTopology& faces_;
  const bool recordParameters_;
  const std::function<void()>& checkpoint_;
  std::map<DomainKey, Line> lines_;
  std::vector<std::array<std::pair<DomainKey, int>, 4>> pieceSides_;  // line key, use index
  std::map<DomainKey, uint32_t> points_;
  TriangleMesh mesh_;
};

void Tessellator::collectSides() {
  pieceSides_.resize(plan_.pieces.size());
  for (uint32_t p = 0; p < plan_.pieces.size(); ++p) {
    const PatchDomain& d = plan_.pieces[p].domain;
    for (int side = 0; side < 4; ++side) {
      double s0, t0, s1, t1, u0, v0, u1, v1;
      sidePoint(side, 0, s0, t0);
      sidePoint(side, 1, s1, t1);
      d.map(s0, t0, u0, v0);
      d.map(s1, t1, u1, v1);
      bool alongU = v0 == v1;
      double from, to;
      DomainKey key = lineKey(faces_, d.baseFace, d.subFace, u0, v0, alongU, from);
      lineKey(faces_, d.baseFace, d.subFace, u1, v1, alongU, to);
      Line& line = lines_[key];
      pieceSides_[p][side] = {key, int(line.uses.size())};
      line.uses.push_back({p, side, from, to});
    }
  }
}

// Elementary intervals between all side ends on a line; each takes the finest level any side
// covering it needs (its level scaled to the interval's share of the side).
void Tessellator::resolveLines() {
  for (auto& [key, line] : lines_) {
    for (const SideUse& use : line.uses) {
      line.breaks.push_back(use.from);
      line.breaks.push_back(use.to);
    }
    std::sort(line.breaks.begin(), line.breaks.end());
    line.breaks.erase(std::unique(line.breaks.begin(), line.breaks.end()), line.breaks.end());
    const size_t intervals = line.breaks.size() - 1;
    line.levels.assign(intervals, 1);
    line.interiorVertices.resize(intervals);
    std::vector<int> owner(intervals, -1);
    for (size_t u = 0; u < line.uses.size(); ++u) {
      const SideUse& use = line.uses[u];
      double lo = std::min(use.from, use.to), hi = std::max(use.from, use.to);
      int level = plan_.pieces[use.piece].level;
      for (size_t i = 0; i < intervals; ++i) {
        if (line.breaks[i] < lo || line.breaks[i + 1] > hi) continue;
        double share = (line.breaks[i + 1] - line.breaks[i]) / (hi - lo);
        line.levels[i] = std::max(line.levels[i], int(std::ceil(level * share - 1e-9)));
        if (owner[i] < 0) owner[i] = int(u);
      }
    }
    for (size_t i = 0; i < intervals; ++i) {
      if (owner[i] < 0) continue;
      const SideUse& use = line.uses[owner[i]];
      for (int k = 1; k < line.levels[i]; ++k) {
        double parameter = line.breaks[i] + (line.breaks[i + 1] - line.breaks[i]) * k / line.levels[i];
        double s, t;
        sidePoint(use.side, (parameter - use.from) / (use.to - use.from), s, t);
        line.interiorVertices[i].push_back(vertexAt(use.piece, s, t));
      }
    }
  }
}

uint32_t Tessellator::vertexAt(uint32_t p, double s, double t) {
  const BezierPiece& piece = plan_.pieces[p];
  PatchSample sample = evaluateBezier(piece.bezier.data(), s, t);
  Vec3d normal = cross(sample.dPds, sample.dPdt);
  if (piece.kind == PieceKind::kInnermost && s == 0 && t == 0 && length(plan_.evNormals[piece.ring]) > 0) {
    normal = plan_.evNormals[piece.ring];
  }
  double l = length(normal);
  normal = l > 0 ? normal * (1.0 / l) : Vec3d(0, 0, 1);
  double u, v;
  piece.domain.map(s, t, u, v);
  mesh_.positions.push_back(Vec3(sample.position));
  mesh_.normals.push_back(Vec3(normal));
  mesh_.vertexFace.push_back(piece.domain.baseFace);
  mesh_.vertexSubFace.push_back(piece.domain.subFace);
  mesh_.vertexUv.insert(mesh_.vertexUv.end(), {u, v});
  return uint32_t(mesh_.positions.size() - 1);
}

uint32_t Tessellator::pointVertex(uint32_t p, double s, double t) {
  const PatchDomain& d = plan_.pieces[p].domain;
  double u, v;
  d.map(s, t, u, v);
  DomainKey key = pointKey(faces_, d.baseFace, d.subFace, u, v);
  auto found = points_.find(key);
  if (found != points_.end()) return found->second;
  uint32_t index = vertexAt(p, s, t);
  points_.emplace(key, index);
  return index;
}

// The vertices along one side, start corner to end corner, with their position phi on the side.
std::vector<Tessellator::Corner> Tessellator::sideVertices(uint32_t p, int side) {
  const auto& [key, useIndex] = pieceSides_[p][side];
  const Line& line = lines_.at(key);
  const SideUse& use = line.uses[useIndex];
  std::vector<Corner> result;
  double lo = std::min(use.from, use.to), hi = std::max(use.from, use.to);
  auto corner = [&](uint32_t vertex, double parameter) {
    Corner c{vertex, (parameter - use.from) / (use.to - use.from), 0, 0};
    sidePoint(side, c.phi, c.s, c.t);
    return c;
  };
  for (size_t i = 0; i + 1 < line.breaks.size(); ++i) {
    if (line.breaks[i] < lo || line.breaks[i + 1] > hi) continue;
    Corner start = corner(0, line.breaks[i]);
    start.vertex = pointVertex(p, start.s, start.t);
    result.push_back(start);
    for (int k = 1; k < line.levels[i]; ++k) {
      double parameter = line.breaks[i] + (line.breaks[i + 1] - line.breaks[i]) * k / line.levels[i];
      result.push_back(corner(line.interiorVertices[i][k - 1], parameter));
    }
  }
  Corner end = corner(0, hi);
  end.vertex = pointVertex(p, end.s, end.t);
  result.push_back(end);
  if (use.from > use.to) std::reverse(result.begin(), result.end());  // side runs against the line
  return result;
}

void Tessellator::emitTriangle(const Corner& a, const Corner& b, const Corner& c, uint32_t piece) {
  if (a.vertex == b.vertex || b.vertex == c.vertex || a.vertex == c.vertex) return;
  mesh_.indices.insert(mesh_.indices.end(), {a.vertex, b.vertex, c.vertex});
  mesh_.trianglePiece.push_back(piece);
  if (recordParameters_) mesh_.triangleST.insert(mesh_.triangleST.end(), {a.s, a.t, b.s, b.t, c.s, c.t});
}

void Tessellator::triangulatePiece(uint32_t p) {
  const int n = plan_.pieces[p].level;
  std::array<std::vector<Corner>, 4> sides;
  bool onlyCorners = true;
  for (int side = 0; side < 4; ++side) {
    sides[side] = sideVertices(p, side);
    onlyCorners &= sides[side].size() == 2;
  }
  if (n == 1 && onlyCorners) {
    emitTriangle(sides[0][0], sides[0][1], sides[1][1], p);
    emitTriangle(sides[0][0], sides[1][1], sides[2][1], p);
    return;
  }
  // Inner grid: (n-1)² points at (i/n, j/n); with n == 1 a single centre point.
  const int inner = std::max(n - 1, 1);
  const double step = n == 1 ? 0.5 : 1.0 / n;
  std::vector<Corner> grid(size_t(inner) * inner);
  for (int j = 0; j < inner; ++j) {
    for (int i = 0; i < inner; ++i) {
      double s = (i + 1) * step, t = (j + 1) * step;
      grid[size_t(j) * inner + i] = {vertexAt(p, s, t), 0, s, t};
    }
  }
  auto at = [&](int i, int j) { return grid[size_t(j) * inner + i]; };
  for (int j = 0; j + 1 < inner; ++j) {
    for (int i = 0; i + 1 < inner; ++i) {
      emitTriangle(at(i, j), at(i + 1, j), at(i + 1, j + 1), p);
      emitTriangle(at(i, j), at(i + 1, j + 1), at(i, j + 1), p);
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
        emitTriangle(boundary[a], boundary[a + 1], row[c], p);
        ++a;
      } else {
        emitTriangle(boundary[a], row[c + 1], row[c], p);
        ++c;
      }
    }
  }
}

TriangleMesh Tessellator::run() {
  collectSides();
  resolveLines();
  for (uint32_t p = 0; p < plan_.pieces.size(); ++p) {
    if (checkpoint_ && p % 256 == 0) checkpoint_();
    triangulatePiece(p);
  }
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
