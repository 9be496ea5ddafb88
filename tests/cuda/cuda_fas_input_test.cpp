// The CUDA FAS host API refuses bad input with a TesseraError before it touches CUDA, so these
// run on every machine, device or not.
#include <gtest/gtest.h>

#include <string>

#include "core/base/error.h"
#include "gpu/cuda/cuda_fas.h"
#include "gpu/cuda/device_info.h"

namespace tessera::cuda {
namespace {

// Runs `call`, expects a TesseraError of `kind` whose message contains `words`.
template <class Call>
void expectRefused(Call call, ErrorKind kind, const std::string& words) {
  try {
    call();
    ADD_FAILURE() << "accepted; expected an error mentioning \"" << words << "\"";
  } catch (const TesseraError& error) {
    EXPECT_EQ(int(error.kind()), int(kind)) << error.what();
    EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
  }
}

const float kSomeRings[1] = {0.0f};

TEST(CudaFasInput, RefusesDepthOutsideOneToTwentyFour) {
  RingRules rules = makeRingRules({5, false}, nullptr, false);
  expectRefused([&] { validateCudaFasInput(rules, 0, 1, kSomeRings); }, ErrorKind::kInvalidInput,
                "depth must be at least 1");
  expectRefused([&] { refineRingsCuda(rules, 25, 1, kSomeRings); }, ErrorKind::kLimitExceeded,
                "depth 25 exceeds the limit of 24");
}

TEST(CudaFasInput, RefusesDegenerateRingsAndBadCounts) {
  expectRefused(
      [] {
        refineRingsCuda(CudaRingBatch{1, 4, 1}, kSomeRings);
      },
      ErrorKind::kInvalidInput, "closed ring needs valence >= 2");
  expectRefused(
      [] {
        refineRingsCuda(makeRingRules({0, true}, nullptr, false), 4, 1, kSomeRings);
      },
      ErrorKind::kInvalidInput, "open ring needs at least 1 face");
  expectRefused(
      [] {
        refineRingsCuda(CudaRingBatch{5, 4, -1}, kSomeRings);
      },
      ErrorKind::kInvalidInput, "must not be negative");
  expectRefused(
      [] {
        refineRingsCuda(CudaRingBatch{5, 4, 3}, nullptr);
      },
      ErrorKind::kInvalidInput, "null ring array");
}

TEST(CudaFasInput, RefusesCreaseSpokesOutsideTheRing) {
  RingRules rules = makeRingRules({5, false}, nullptr, false);
  rules.evRule = EvRule::kCrease;
  rules.creaseSpokeA = 1;
  rules.creaseSpokeB = 5;
  expectRefused([&] { validateCudaFasInput(rules, 3, 1, kSomeRings); }, ErrorKind::kInvalidInput,
                "crease spoke 5 outside 0..4");
}

TEST(CudaFasInput, EmptyBatchNeedsNoDevice) {
  EXPECT_TRUE(refineRingsCuda(CudaRingBatch{5, 4, 0}, nullptr).empty());
}

TEST(CudaFasInput, OutputSizeIsRefineRingsLayout) {
  EXPECT_EQ(cudaFasOutputFloats({5, false}, 4, 3), size_t(3) * 4 * 61 * 3);
  EXPECT_EQ(cudaFasOutputFloats({3, true}, 2, 1), size_t(2) * (12 * 3 + 1 + 3) * 3);
}

// Without a device the API says so in CUDA's words; with one this test has nothing to check.
TEST(CudaFasInput, MissingDeviceIsReportedAsUnsupported) {
  if (queryCudaDevice().available) GTEST_SKIP() << "a CUDA device is present";
  const float ring[3 * 31] = {};
  expectRefused(
      [&] {
        refineRingsCuda(CudaRingBatch{5, 3, 1}, ring);
      },
      ErrorKind::kUnsupported, "no CUDA device: ");
}

}  // namespace
}  // namespace tessera::cuda
