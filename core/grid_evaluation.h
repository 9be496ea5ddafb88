// Uniform sampling of planned pieces (the paper's Table 2 setup): every piece evaluated on its
// (N+1)×(N+1) grid of parameters i/N, positions written to one array. Bernstein weights are
// computed once per level, each piece is evaluated as four column curves then rows (8 samples per
// AVX2 vector), and pieces are spread over all cores.
#pragma once

#include <cstddef>
#include <vector>

#include "core/tessellation_plan.h"

namespace tessera {

// Where each piece's samples start in the output, then the total; reuses `offsets`' storage.
void gridOffsets(const std::vector<BezierPiece>& pieces, std::vector<size_t>& offsets);

// kAvx2 computes 8 samples per instruction in struct-of-arrays registers, without FMA and in the
// scalar code's order of operations, so both give the same bits; kScalar is the reference the
// tests hold the vector code to.
enum class GridKernel { kAvx2, kScalar };

// Writes (N+1)² positions per piece, row-major in t then s, at out + offsets[p].
void evaluatePieceGrids(const std::vector<BezierPiece>& pieces, const std::vector<size_t>& offsets,
                        Vec3* out, GridKernel kernel = GridKernel::kAvx2);

}  // namespace tessera
