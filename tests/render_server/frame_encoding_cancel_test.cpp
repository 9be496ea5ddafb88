// The encoders and the image's checksum poll the call's cancellation as they go (issue 47: every
// render stage ends within a second of a deadline): an 8192-wide PNG is written 256 rows at a time
// and the SHA-256 taken 16 MiB at a time, with a poll between, and a token that fires stops them
// with OperationCancelled. Without it, a 4096 x 4096 PNG took ~1.5 s here in one piece.
#include <gtest/gtest.h>

#include <atomic>
#include <string_view>
#include <vector>

#include "core/base/sha256.h"
#include "server/render/frame_digest.h"
#include "server/render/frame_encoder.h"

namespace tessera::server {
namespace {

// A token that fires at its `firesAt`-th poll, counting them.
struct CountingToken {
  std::atomic<int> polls{0};
  int firesAt;
  explicit CountingToken(int n) : firesAt(n) {}
  CancellationToken token() {
    return CancellationToken([this] { return ++polls >= firesAt; });
  }
};

std::vector<uint8_t> gradient(uint32_t width, uint32_t height) {
  std::vector<uint8_t> rgba(size_t(width) * height * 4);
  for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = uint8_t((i * 7) ^ (i >> 11));
  return rgba;
}

TEST(FrameEncodingCancel, EveryEncoderPollsBandByBandAndStopsWhenTheTokenFires) {
  const uint32_t width = 512, height = 2048;  // 8 bands of 256 rows
  const std::vector<uint8_t> rgba = gradient(width, height);
  const std::vector<float> depth(size_t(width) * height, 0.5f);
  const FrameImage image{width, height, rgba, depth};
  for (FrameFormat format : {FrameFormat::kPng, FrameFormat::kJpeg, FrameFormat::kExr}) {
    CountingToken never(1 << 30);
    EXPECT_FALSE(encodeFrame(image, EncodingSettings{format}, never.token()).empty());
    EXPECT_GE(never.polls.load(), 8)
        << formatName(format) << ": polled once per band of rows at least";
    CountingToken third(3);
    EXPECT_THROW(encodeFrame(image, EncodingSettings{format}, third.token()), OperationCancelled)
        << formatName(format);
    EXPECT_EQ(third.polls.load(), 3) << formatName(format) << ": stopped at the poll that fired";
  }
}

TEST(FrameEncodingCancel, TheChecksumIsSha256AndStopsWhenTheTokenFires) {
  const std::vector<uint8_t> bytes = gradient(4096, 2048);  // 32 MiB: two slices
  CountingToken never(1 << 30);
  EXPECT_EQ(frameSha256Hex(bytes, never.token()),
            sha256Hex(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size())));
  EXPECT_EQ(never.polls.load(), 2);
  CountingToken second(2);
  EXPECT_THROW(frameSha256Hex(bytes, second.token()), OperationCancelled);
}

}  // namespace
}  // namespace tessera::server
