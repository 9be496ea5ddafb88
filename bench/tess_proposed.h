// Proposed changes to core/tessellation_plan.cpp and core/grid_evaluation.cpp for the uniform
// (Table 2) path, prototyped here and measured as BM_TessUniform_Proposed beside the library
// (bench/TESS-RESULTS.md). The output is required to be bit-identical to core's
// planTessellation(uniformLevel = p) + evaluatePieceGrids: same pieces, same order, same float
// operations in the same order. What changes is where the time went:
//
//  1. The plan keeps its arrays between frames (a planner object instead of a fresh
//     TessellationPlan per call): no page faults and no zero-fill of ~270 B per piece each frame.
//  2. Ring pieces are written straight into their final slots (a prefix sum over rings of
//     owned sectors × (3·depth + 1)), in parallel; no per-ring vectors, no serial insert.
//  3. Uniform mode skips the FMM86 curvature bound and the per-ring depth bound, which only
//     feed TessellationPlan::guaranteedBound (nothing in Table 2 reads it).
//  4. Grid evaluation reads a struct of arrays (Bézier nets stored x[16] y[16] z[16], and
//     levels: 196 B per piece instead of the whole BezierPiece) and is vectorized with AVX2 (no
//     FMA, so every sample rounds exactly as the scalar code): the four column curves of a row
//     in one SSE vector per coordinate, then 8 samples of the row at a time (the last vector
//     overlapping the previous one instead of a scalar tail); pieces with N + 1 < 8 samples per
//     row are evaluated 8 samples at a time across rows. Stored as xyz triples.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "core/patch_set.h"
#include "core/vec3.h"

namespace tessera::bench::proposed {

class UniformPlanner {
 public:
  // Plans every piece at uniform level p, reusing this object's storage.
  void plan(const PatchSet& patches, int p);
  // (N+1)² samples per piece, row-major in t then s, pieces one after another.
  void evaluate(Vec3* out) const;

  size_t samples() const { return offsets_.empty() ? 0 : offsets_.back(); }
  size_t pieces() const { return levels_.size(); }

 private:
  // Bernstein weights of the parameters i/N (bernsteinBasis in float, as core's table).
  struct LevelWeights {
    std::vector<float> w[4];  // w[k][i], padded with zeros to a multiple of 8
    // Levels with N + 1 < 8: the (N+1)² samples flattened, 8 at a time: each sample's s index
    // and t index (lane permutations of vectors over i and over j).
    std::vector<int> sIndex, tIndex;
  };
  const LevelWeights& weights(int level) const { return weights_[level]; }

  // Bézier nets as x[16], y[16], z[16]: a row of four control points is one SSE vector.
  std::vector<std::array<float, 48>> bezier_;
  std::vector<int> levels_;
  std::vector<size_t> offsets_;     // first sample of each piece, then the total
  std::vector<size_t> ringFirst_;   // first piece of each ring, then the total
  std::vector<int> ringDepth_;
  std::vector<LevelWeights> weights_;  // by level (powers of two up to p, and 1)
};

}  // namespace tessera::bench::proposed
