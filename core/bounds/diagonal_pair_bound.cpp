#include "core/bounds/diagonal_pair_bound.h"

#include <algorithm>
#include <cmath>

namespace tessera {

// A square of a leaf ([x, x + s]² of an ancestor's square, within r of the surface) against the
// ancestor's pair through a diagonal map ρ (docs/ADAPTIVE.md §3b). A square spanning grid cells
// is split into them; one meeting both triangles of its cell is split three times more, then
// bounded against each triangle's affine pair ∘ ρ over all of it. Each square is bounded cheaply
// first from the leaf's own bounds (f − B, then the bilinear B − pair ∘ ρ at its corners); it is
// split, or its net bounded by de Casteljau, only where the cheap bound could raise the maxima;
// without a net (a node standing for its leaves) the cheap bounds are the bounds.
void pieceAgainstDiagonal(const LazyNet* net, double r, const LeafOwn& own, double x, double y, double s,
                          const DiagonalMap& map, double& pair, std::array<double, 4>& bows, double abortAbove) {
  if (pair > abortAbove) return;
  auto quarters = [&] {
    for (int q = 0; q < 4; ++q) {
      const LazyNet quadrant(net, q);
      pieceAgainstDiagonal(net ? &quadrant : nullptr, r, own, x + (q & 1) * s / 2, y + (q >> 1) * s / 2, s / 2, map, pair, bows,
                           abortAbove);
    }
  };
  if (map.spans(x, y, s)) return quarters();
  const double cx[4] = {x, x + s, x + s, x}, cy[4] = {y, y, y + s, y + s};
  Vec3d leafB[4];
  for (int k = 0; k < 4; ++k) leafB[k] = own.bilinear(cx[k], cy[k]);
  const int i = map.column(x), j = map.row(y);
  const int met = map.trianglesMet(i, j, x, y, s);
  // The cheap bounds, each triangle's affine function extended over the whole square.
  bool open = false;
  Vec3d target[2][4];
  double cheap[2] = {0, 0};
  for (int h = 0; h < 2; ++h) {
    if (!(met >> h & 1)) continue;
    double gap2 = 0;
    for (int k = 0; k < 4; ++k) {
      target[h][k] = map.pairOverTriangle(i, j, h, cx[k], cy[k]);
      gap2 = std::max(gap2, lengthSquared(target[h][k] - leafB[k]));
    }
    cheap[h] = own.pair + std::sqrt(gap2);
    open = open || cheap[h] > pair;
  }
  const bool touches[4] = {y == 0, x + s == 1, y + s == 1, x == 0};
  Vec3d chordEnds[4][2];
  double cheapBow[4] = {0, 0, 0, 0};
  for (int side = 0; side < 4; ++side) {
    if (!touches[side]) continue;
    int from, to;
    sideCorners(side, from, to);
    chordEnds[side][0] = map.pairOnBoundary(cx[from], cy[from]);
    chordEnds[side][1] = map.pairOnBoundary(cx[to], cy[to]);
    cheapBow[side] = own.bows[side] + std::sqrt(std::max(lengthSquared(chordEnds[side][0] - leafB[from]),
                                                         lengthSquared(chordEnds[side][1] - leafB[to])));
  }
  if (met == 3 && open && map.relativeSize(i, j, s) > 0.125) return quarters();
  for (int side = 0; side < 4; ++side) {
    if (!touches[side] || cheapBow[side] <= bows[side]) continue;
    const double exact = net ? r + sideChordDistance(net->get(), side, chordEnds[side][0], chordEnds[side][1]) : INFINITY;
    bows[side] = std::max(bows[side], std::min(cheapBow[side], exact));
  }
  for (int h = 0; h < 2; ++h) {
    if (!(met >> h & 1) || cheap[h] <= pair) continue;
    // pair ∘ ρ is affine here: its bilinear net is itself. The hull of the difference first; split
    // by de Casteljau (tighter, dearer) only where the hull would raise the maximum.
    if (!net) {
      pair = std::max(pair, cheap[h]);
      continue;
    }
    const BezierNet affine = bilinearNet(target[h]);
    const double hull = r + netDistance(net->get(), affine);
    if (hull <= pair) continue;
    pair = std::max(pair, std::min({cheap[h], hull, r + splitNetDistance(net->get(), affine)}));
  }
}

}  // namespace tessera
