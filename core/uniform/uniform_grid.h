// The paper's Table 2 workload (§6.1): the whole limit surface sampled at a uniform level p,
// everything before rasterization. The pieces are those of planTessellation's uniform mode, in its
// order (regular patches, then ring by ring the FAS patches of every level and the innermost
// Béziers, uniform_levels.h), each on the (N+1)×(N+1) grid of parameters i/N. Nothing is
// converted or copied that need not be: regular patches are evaluated straight from the patch
// set's B-spline nets and FAS patches from the nets FAS made, with B-spline weights; only the
// innermost pieces are Bézier nets. No distance bound is proved (planTessellation does that).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/math/grid_sample.h"
#include "core/rings/patch_set.h"

namespace tessera {

struct GridPiece {
  uint16_t level = 1;  // N: an (N+1)×(N+1) grid
  NetBasis basis = NetBasis::kBSpline;
  bool operator==(const GridPiece&) const = default;
};

// Refers to the nets of the patch set it was planned from: keep that alive while using it.
struct UniformGrid {
  size_t regularPieces = 0;
  // Piece q's net is regular.bspline[q] below regularPieces, else ringNets[q - regularPieces].
  std::vector<GridPiece> pieces;
  std::vector<ControlNet> ringNets;  // absolute positions
  std::vector<size_t> ringFirst;     // ring r's pieces are [ringFirst[r], ringFirst[r + 1])
  std::vector<size_t> offsets;       // piece q's samples start at offsets[q]; the last is the total
  size_t samples() const { return offsets.empty() ? 0 : offsets.back(); }
};

// Plans level p (1..kMaxUniformLevel) into `grid`, reusing its storage: a viewer that re-plans
// every frame allocates nothing once the counts settle. Rings are refined in parallel straight
// into their final slots.
void planUniformGrid(const PatchSet& patches, int p, UniformGrid& grid);

// kAvx2 computes 8 samples per instruction in struct-of-arrays registers, without FMA and in the
// scalar code's order of operations, so both give the same bits; kScalar is the reference the
// tests hold the vector code to.
enum class GridKernel { kAvx2, kScalar };

// Writes (N+1)² positions per piece, row-major in t then s, at out + grid.offsets[q].
void evaluateUniformGrid(const PatchSet& patches, const UniformGrid& grid, Vec3* out,
                         GridKernel kernel = GridKernel::kAvx2);

}  // namespace tessera
