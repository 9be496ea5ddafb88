// One sample of a uniform grid piece (core/uniform/uniform_grid.h), written once for the CPU reference
// and the CUDA kernel (gpu/cuda/uniform_grid_kernel.cu): the weights of a basis at i/N, computed
// in double and rounded once to float, and the sample from a 16-point net in float, four column
// curves c_k(t) = Σ_r B_r(t) b[r][k] and then Σ_k B_k(s) c_k, each sum left to right. With no
// multiply-add contraction (-ffp-contract=off here, --fmad=false in nvcc) every caller rounds
// alike, so the CPU and GPU grids are equal bit for bit (MATH.md §5).
#pragma once

#include <cstdint>

#include "core/base/host_device.h"
#include "core/base/vec3.h"
#include "core/math/bicubic.h"

namespace tessera {

enum class NetBasis : uint8_t { kBSpline, kBezier };

// The four weights of `basis` at the parameter i / level.
TESSERA_HD void gridWeights(NetBasis basis, int i, int level, float w[4]) {
  double value[4], unused[4];
  const double t = double(i) / double(level);
  if (basis == NetBasis::kBSpline) {
    bsplineBasis(t, value, unused);
  } else {
    cubicBernstein(t, value, unused);
  }
  for (int k = 0; k < 4; ++k) w[k] = float(value[k]);
}

// Column curve k at the weights wt of one row: ((b0 w0 + b1 w1) + b2 w2) + b3 w3.
TESSERA_HD Vec3 gridColumn(const Vec3* net, int k, const float wt[4]) {
  return net[k] * wt[0] + net[4 + k] * wt[1] + net[8 + k] * wt[2] + net[12 + k] * wt[3];
}

// The sample at weights ws (along s) and wt (along t) from the column curves of its row.
TESSERA_HD Vec3 gridSampleFromColumns(const Vec3 column[4], const float ws[4]) {
  return column[0] * ws[0] + column[1] * ws[1] + column[2] * ws[2] + column[3] * ws[3];
}

TESSERA_HD Vec3 gridSample(const Vec3* net, const float ws[4], const float wt[4]) {
  const Vec3 column[4] = {gridColumn(net, 0, wt), gridColumn(net, 1, wt), gridColumn(net, 2, wt),
                          gridColumn(net, 3, wt)};
  return gridSampleFromColumns(column, ws);
}

}  // namespace tessera
