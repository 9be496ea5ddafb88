// Planning (paper §5): for each ring a FAS depth from the depth tables so that the innermost
// Bézier approximation stays within ηε; then every piece of surface (regular patches, FAS
// patches, innermost Béziers) as a bicubic Bézier with a tessellation level from the FMM86
// bound on its second differences (MATH.md §4), so that triangles stay within what is left of ε.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/request/tessellation_options.h"
#include "core/rings/patch_set.h"

namespace tessera {

enum class PieceKind : uint8_t { kRegular, kFas, kInnermost };

struct BezierPiece {
  std::array<Vec3, 16> bezier;  // row-major, s along columns
  PatchDomain domain;
  PieceKind kind = PieceKind::kRegular;
  uint8_t depth = 0;             // refinement level below the base face
  int level = 1;                 // tessellation level N (an N×N grid)
  float approximationBound = 0;  // distance to the limit surface (0: exact piece)
  float tessellationBound = 0;   // FMM86 bound of the N×N triangulation
  float tolerance = 0;           // ε this piece was planned for (object space)
  int ring = -1;                 // innermost pieces: their ring (its EV is the (0,0) corner)
};

struct TessellationPlan {
  std::vector<BezierPiece> pieces;
  std::vector<Vec3d> evNormals;  // per ring: exact limit normal at the EV, or zero if not known
  int rings = 0;
  double averageDepth = 0;
  int maxDepth = 0;
  double guaranteedBound = 0;  // max over pieces of approximation + tessellation bound
  double tolerance = 0;        // ε in object space (the smallest one in pixel mode)
};

// Throws TesseraError (kInvalidInput) for bad options (validateTessellationOptions) before any work.
TessellationPlan planTessellation(const PatchSet& patches, const TessellationOptions& options);

// The same plan written into `plan`, reusing its storage: an application that re-plans every
// frame (the interactive use the paper targets) then allocates, zero-fills and page-faults
// nothing once the piece count settles. Ring pieces are planned in parallel straight into their
// final slots (piece counts per ring are known before any FAS). If options.checkpoint throws,
// `plan` is left half-written.
void planTessellation(const PatchSet& patches, const TessellationOptions& options,
                      TessellationPlan& plan);

// FMM86 on a bicubic Bézier: the smallest N with (M_uu + 2 M_uv + M_vv) / (8 N²) ≤ ε, and the
// bound that N achieves.
int tessellationLevel(const Vec3* bezier, double epsilon, double& achievedBound);

}  // namespace tessera
