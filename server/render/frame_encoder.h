// Encodes a rendered frame into the bytes RenderService streams: PNG, JPEG or OpenEXR through
// OpenImageIO, written straight to memory (an ImageOutput on an IOVecOutput proxy: no temporary
// files), or the raw RGBA buffer. Builds without OpenImageIO (those without the renderer)
// encode RAW_RGBA only and refuse the rest with RenderUnavailable.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "server/calls/cancellation.h"

namespace tessera::server {

inline constexpr int kDefaultJpegQuality = 90;

enum class FrameFormat { kPng, kJpeg, kExr, kRawRgba };

struct EncodingSettings {
  FrameFormat format = FrameFormat::kPng;
  int jpegQuality = kDefaultJpegQuality;  // 1..100, JPEG only
};

// A frame as the renderer reads it back: rows top to bottom.
struct FrameImage {
  uint32_t width = 0;
  uint32_t height = 0;
  std::span<const uint8_t> rgba;  // 4 bytes per pixel
  std::span<const float> depth;   // window depth per pixel (EXR's Z channel); may be empty
};

// PNG: RGBA8. JPEG: RGB8 (alpha dropped) at jpegQuality. EXR: R, G, B, A as half (the 8-bit
// values / 255) and, when depth is given, Z as float. RAW_RGBA: the rgba bytes unchanged.
// Throws std::invalid_argument for buffers that do not match the size, std::runtime_error
// when the encoder fails, OperationCancelled when `cancel` fires while it works (polled as
// OpenImageIO reports progress, a few times a second on an 8192 x 8192 PNG).
std::vector<uint8_t> encodeFrame(const FrameImage& image, const EncodingSettings& settings,
                                 const CancellationToken& cancel = {});

// "png", "jpeg", "exr", "raw".
const char* formatName(FrameFormat format);

}  // namespace tessera::server
