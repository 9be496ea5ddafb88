// The uniform grid (core/uniform/uniform_grid.h, the paper's Table 2) on a CUDA device, two kernels: one
// thread per piece marks the sample blocks that start in its piece, then one thread per sample,
// each block kGridSamplesPerBlock consecutive samples of the grid's output, finds its piece among
// the few its block spans. What each thread does is written once here as host-device code, so
// that the kernels (uniform_grid_kernel.cu) and the CPU-side simulation
// (tests/cuda/grid_simulation_test.cpp) run the same indexing; the sample itself is
// core/math/grid_sample.h, the CPU reference's own code.
//
// Plain C++ apart from TESSERA_HD: no CUDA types.
#pragma once

#include <cstdint>

#include "core/base/host_device.h"
#include "core/base/vec3.h"
#include "core/math/grid_sample.h"

namespace tessera::cuda {

inline constexpr int kGridSamplesPerBlock = 256;

// The four basis weights at one parameter i/N, one 16-byte load on the device.
struct alignas(16) ParameterWeights {
  float w[4];
};

// A piece as the device reads it: its level and where its basis's weights at 0/N .. N/N start
// in GridView::weights (one table per level and basis in use, filled by core's gridWeights, so
// the device reads the very floats the CPU computes).
struct GridPieceRecord {
  uint32_t level = 0;
  uint32_t weights = 0;
};

// The grid in device memory (or, for the simulation, host memory).
struct GridView {
  const Vec3* nets = nullptr;  // 16 points per piece, in piece order
  const GridPieceRecord* pieces = nullptr;
  const ParameterWeights* weights = nullptr;
  const uint64_t* offsets = nullptr;  // piece q's samples start at offsets[q]; pieceCount + 1
  uint64_t pieceCount = 0;
  uint64_t sampleCount = 0;  // offsets[pieceCount], kept here for the host to size the launch
  uint32_t* blockFirstPiece = nullptr;  // per sample block: the piece of its first sample
  Vec3* out = nullptr;

  TESSERA_HD uint64_t blocks() const {
    return (sampleCount + kGridSamplesPerBlock - 1) / kGridSamplesPerBlock;
  }
};

// The piece q in [lo, hi) with offsets[q] <= sample < offsets[q + 1], by bisection; every piece
// has at least 4 samples, so it is unique.
TESSERA_HD uint64_t findGridPiece(const uint64_t* offsets, uint64_t lo, uint64_t hi,
                                  uint64_t sample) {
  while (hi - lo > 1) {
    const uint64_t mid = lo + (hi - lo) / 2;
    if (offsets[mid] <= sample) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return lo;
}

// First kernel, one thread per piece q: the blocks whose first sample b·K lies in q, that is
// offsets[q] <= b·K < offsets[q + 1]. Every block is marked exactly once. (Thread 0 of each block
// bisecting all pieces instead kept the other threads waiting at a barrier for most of the time.)
TESSERA_HD void markBlockFirstPiece(const GridView& view, uint64_t q) {
  const uint64_t k = kGridSamplesPerBlock;
  const uint64_t begin = (view.offsets[q] + k - 1) / k, end = (view.offsets[q + 1] + k - 1) / k;
  for (uint64_t block = begin; block < end; ++block) view.blockFirstPiece[block] = uint32_t(q);
}

// A block's samples and the pieces they fall in: from its first sample's piece up to the next
// block's (which holds the sample after this block's last).
struct GridBlockRange {
  uint64_t firstSample = 0, endSample = 0;
  uint64_t firstPiece = 0, endPiece = 0;
};

TESSERA_HD GridBlockRange gridBlockRange(const GridView& view, uint64_t block) {
  GridBlockRange range;
  range.firstSample = block * kGridSamplesPerBlock;
  const uint64_t end = range.firstSample + kGridSamplesPerBlock;
  range.endSample = end < view.sampleCount ? end : view.sampleCount;
  range.firstPiece = view.blockFirstPiece[block];
  range.endPiece =
      block + 1 < view.blocks() ? uint64_t(view.blockFirstPiece[block + 1]) + 1 : view.pieceCount;
  return range;
}

// One thread's work: sample (i, j) of its piece, row-major in t then s as on the CPU.
TESSERA_HD void writeGridSample(const GridView& view, const GridBlockRange& range,
                                uint64_t sample) {
  const uint64_t q = findGridPiece(view.offsets, range.firstPiece, range.endPiece, sample);
  const GridPieceRecord piece = view.pieces[q];
  const auto local = uint32_t(sample - view.offsets[q]);  // < 4097², fits 32 bits
  const uint32_t side = piece.level + 1;
  const ParameterWeights ws = view.weights[piece.weights + local % side];
  const ParameterWeights wt = view.weights[piece.weights + local / side];
  view.out[sample] = gridSample(view.nets + 16 * q, ws.w, wt.w);
}

}  // namespace tessera::cuda
