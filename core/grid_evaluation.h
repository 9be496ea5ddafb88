// Uniform sampling of planned pieces (the paper's Table 2 setup): every piece evaluated on its
// (N+1)×(N+1) grid of parameters i/N, positions written to one array. Bernstein weights are
// computed once per level, each piece is evaluated as four column curves then rows, and pieces
// are spread over all cores.
#pragma once

#include <cstddef>
#include <vector>

#include "core/tessellation_plan.h"

namespace tessera {

// Where each piece's samples start in the output; the last entry is the total.
std::vector<size_t> gridOffsets(const std::vector<BezierPiece>& pieces);

// Writes (N+1)² positions per piece, row-major in t then s, at out + offsets[p].
void evaluatePieceGrids(const std::vector<BezierPiece>& pieces, const std::vector<size_t>& offsets,
                        Vec3* out);

}  // namespace tessera
