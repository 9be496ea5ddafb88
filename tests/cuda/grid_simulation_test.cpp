// The uniform-grid kernel's algorithm run on the CPU: gpu/cuda/grid_threads.h compiled by the host
// compiler and driven as uniform_grid_kernel.cu drives it (each block's range found once, then
// its threads), blocks in reverse order and threads shuffled, into NaN-poisoned output. Equal bit
// for bit to the CPU's scalar reference (evaluateUniformGrid), so a sample written twice, missed
// or taken from the wrong piece or weights fails. Runs on every machine.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>
#include <string>

#include "gpu/cuda/cuda_uniform_grid.h"
#include "gpu/cuda/grid_threads.h"
#include "tests/cuda/grid_cases.h"

namespace tessera::cuda {
namespace {

// Both kernels' threads in shuffled order: every piece's marks, then every block's samples.
void markBlocks(const GridView& view, std::mt19937& random) {
  std::vector<uint64_t> pieces(view.pieceCount);
  std::iota(pieces.begin(), pieces.end(), 0);
  std::shuffle(pieces.begin(), pieces.end(), random);
  for (uint64_t q : pieces) markBlockFirstPiece(view, q);
}

std::vector<Vec3> simulateUniformGrid(const GridUpload& upload, uint32_t seed) {
  const float poison = std::numeric_limits<float>::quiet_NaN();
  std::vector<Vec3> out(upload.offsets.back(), Vec3(poison, poison, poison));
  std::vector<uint32_t> blockFirstPiece;
  GridView view;
  view.nets = upload.nets.data();
  view.pieces = upload.pieces.data();
  view.weights = upload.weights.data();
  view.offsets = upload.offsets.data();
  view.pieceCount = upload.pieces.size();
  view.sampleCount = upload.offsets.back();
  view.out = out.data();
  blockFirstPiece.assign(view.blocks(), UINT32_MAX);  // a block left unmarked reads past the end
  view.blockFirstPiece = blockFirstPiece.data();
  std::mt19937 random(seed);
  markBlocks(view, random);
  std::vector<int> threads(kGridSamplesPerBlock);
  std::iota(threads.begin(), threads.end(), 0);
  for (uint64_t block = view.blocks(); block-- > 0;) {
    const GridBlockRange range = gridBlockRange(view, block);
    std::shuffle(threads.begin(), threads.end(), random);
    for (int thread : threads) {
      const uint64_t sample = range.firstSample + uint64_t(thread);
      if (sample < range.endSample) writeGridSample(view, range, sample);
    }
  }
  return out;
}

long firstDifference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.size() != b.size()) return 0;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::memcmp(&a[i], &b[i], sizeof(Vec3)) != 0) return long(i);
  }
  return -1;
}

TEST(GridSimulation, EqualsTheCpuReferenceBitForBit) {
  testing::forEachGridCase(GridKernel::kScalar, [](const std::string& name, int p,
                                                   const PatchSet& patches, const UniformGrid& grid,
                                                   const std::vector<Vec3>& expected) {
    const std::vector<Vec3> simulated = simulateUniformGrid(makeGridUpload(patches, grid), 7u + p);
    EXPECT_EQ(firstDifference(simulated, expected), -1) << name << " p=" << p;
  });
}

TEST(GridSimulation, BlockRangesCoverEverySampleOnce) {
  // Pieces of 4, 9 and 4225 samples: blocks that hold many pieces, one piece, or part of one.
  GridUpload upload;
  for (int level : {1, 2, 64, 1, 1, 2, 64, 64, 1}) {
    const uint64_t first = upload.offsets.empty() ? 0 : upload.offsets.back();
    if (upload.offsets.empty()) upload.offsets.push_back(0);
    upload.offsets.push_back(first + uint64_t(level + 1) * uint64_t(level + 1));
    upload.pieces.push_back({uint32_t(level), 0});
  }
  GridView view;
  view.offsets = upload.offsets.data();
  view.pieceCount = upload.pieces.size();
  view.sampleCount = upload.offsets.back();
  std::vector<uint32_t> blockFirstPiece(view.blocks(), UINT32_MAX);
  view.blockFirstPiece = blockFirstPiece.data();
  std::mt19937 random(3);
  markBlocks(view, random);
  uint64_t covered = 0;
  for (uint64_t block = 0; block < view.blocks(); ++block) {
    ASSERT_LT(blockFirstPiece[block], view.pieceCount) << "block " << block << " not marked";
    const GridBlockRange range = gridBlockRange(view, block);
    EXPECT_EQ(range.firstSample, covered);
    covered = range.endSample;
    for (uint64_t sample = range.firstSample; sample < range.endSample; ++sample) {
      const uint64_t q = findGridPiece(view.offsets, range.firstPiece, range.endPiece, sample);
      ASSERT_LE(upload.offsets[q], sample);
      ASSERT_LT(sample, upload.offsets[q + 1]);
    }
  }
  EXPECT_EQ(covered, view.sampleCount);
}

}  // namespace
}  // namespace tessera::cuda
