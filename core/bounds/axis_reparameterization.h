// A monotone reparameterization of one axis of a node's square, for the geometric pair bound
// (docs/ADAPTIVE.md §3a): the same triangles compared with f ∘ φ, φ(x, y) = (α(x), β(y)), instead
// of f at the same parameters. α is piecewise linear with breakpoints at multiples of 1/16 that no
// piece under the node spans, so f ∘ φ is, on every piece, the piece itself over a rectangle of
// other corners: its Bézier net is unchanged and every convex-hull bound still applies.
#pragma once

#include <array>
#include <cstdint>

namespace tessera {

// α through its inverse: the preimage t = α⁻¹(x) of every x = m / kCells (α is affine between
// consecutive breakpoints, and so is α⁻¹). The identity unless the builder found breakpoints.
class AxisMap {
 public:
  static constexpr int kCells = 16;  // at most 64: AxisMapBuilder keeps one bit per breakpoint

  AxisMap();
  // The preimage of x ∈ [0, 1]; exact at breakpoints, affine between them.
  double preimage(double x) const;
  bool isIdentity() const { return identity_; }

  friend class AxisMapBuilder;

 private:
  std::array<double, kCells + 1> t_;
  bool identity_ = true;
};

// Gathers what picks α: which multiples of 1/kCells a piece spans (they cannot be breakpoints),
// and at the others, where the surface there projects onto the node's bilinear (the tangential
// position the triangles would give it). α then sends each breakpoint's mean projection to it.
class AxisMapBuilder {
 public:
  // A piece covering [x0, x1] along the axis.
  void addPiece(double x0, double x1);
  // A surface point at x whose projection onto the bilinear's line across the axis is at t.
  void addSample(double x, double t);
  // Breakpoints kept in order, each at least kMinStep past the previous preimage; others dropped.
  AxisMap build() const;

 private:
  uint64_t spanned_ = 0;  // bit m: m / kCells lies strictly inside a piece
  std::array<double, AxisMap::kCells + 1> sum_{};
  std::array<uint32_t, AxisMap::kCells + 1> count_{};
};

}  // namespace tessera
