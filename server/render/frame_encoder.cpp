#include "server/render/frame_encoder.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#if TESSERA_WITH_RENDER
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#else
#include "server/render/render_backend.h"
#endif

namespace tessera::server {
namespace {

void checkBuffers(const FrameImage& image) {
  size_t pixels = size_t(image.width) * image.height;
  if (pixels == 0) throw std::invalid_argument("cannot encode an empty frame");
  if (image.rgba.size() != 4 * pixels) {
    throw std::invalid_argument("frame colour buffer does not match its size");
  }
  if (!image.depth.empty() && image.depth.size() != pixels) {
    throw std::invalid_argument("frame depth buffer does not match its size");
  }
}

#if TESSERA_WITH_RENDER

// The file name only selects the format plugin: with an IOProxy nothing touches the disk.
const char* pluginName(FrameFormat format) {
  switch (format) {
    case FrameFormat::kJpeg:
      return "frame.jpg";
    case FrameFormat::kExr:
      return "frame.exr";
    default:
      return "frame.png";
  }
}

// Rows written between two polls of the call's cancellation: 256 rows of an 8192-wide PNG take
// ~0.1 s here. (write_image's own progress callback comes every 64 MiB of pixels, seconds apart.)
constexpr int kRowsPerPoll = 256;

// Writes the image band by band, polling `cancel` between bands.
bool writeRows(OIIO::ImageOutput& output, OIIO::TypeDesc pixelType, const void* pixels, int width,
               int height, OIIO::stride_t pixelStride, OIIO::stride_t rowStride,
               const CancellationToken& cancel) {
  if (pixelStride == OIIO::AutoStride)
    pixelStride = OIIO::stride_t(pixelType.size()) * output.spec().nchannels;
  if (rowStride == OIIO::AutoStride) rowStride = pixelStride * width;
  for (int y = 0; y < height; y += kRowsPerPoll) {
    cancel.throwIfCancelled();
    const int end = std::min(height, y + kRowsPerPoll);
    const auto* first = static_cast<const uint8_t*>(pixels) + OIIO::stride_t(y) * rowStride;
    if (!output.write_scanlines(y, end, 0, pixelType, first, pixelStride, rowStride)) return false;
  }
  return true;
}

std::vector<uint8_t> writeWithOpenImageIO(OIIO::ImageSpec spec, OIIO::TypeDesc pixelType,
                                          const void* pixels, FrameFormat format,
                                          const CancellationToken& cancel,
                                          OIIO::stride_t pixelStride = OIIO::AutoStride,
                                          OIIO::stride_t rowStride = OIIO::AutoStride) {
  const std::string name = formatName(format);
  std::vector<uint8_t> bytes;
  OIIO::Filesystem::IOVecOutput memory(bytes);
  void* proxy = &memory;
  spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  auto output = OIIO::ImageOutput::create(pluginName(format));
  if (!output)
    throw std::runtime_error("OpenImageIO has no " + name + " writer: " + OIIO::geterror());
  if (!output->open(pluginName(format), spec)) {
    throw std::runtime_error("cannot start the " + name + " encoder: " + output->geterror());
  }
  bool written = writeRows(*output, pixelType, pixels, spec.width, spec.height, pixelStride,
                           rowStride, cancel);
  bool closed = output->close();
  if (!written || !closed)
    throw std::runtime_error(name + " encoding failed: " + output->geterror());
  return bytes;
}

// zlib level 3 instead of OpenImageIO's default 6: on a 1280x720 frame of bigguy it halves the
// encoding time (91 -> 48 ms on the 2-core development box) for about a third more bytes, the
// better trade for frames sent while the client waits.
constexpr int kPngCompressionLevel = 3;

std::vector<uint8_t> encodePng(const FrameImage& image, const CancellationToken& cancel) {
  OIIO::ImageSpec spec(int(image.width), int(image.height), 4, OIIO::TypeDesc::UINT8);
  spec.attribute("png:compressionLevel", kPngCompressionLevel);
  return writeWithOpenImageIO(spec, OIIO::TypeDesc::UINT8, image.rgba.data(), FrameFormat::kPng,
                              cancel);
}

// JPEG has no alpha: the first three bytes of each pixel are written (strided, no copy).
std::vector<uint8_t> encodeJpeg(const FrameImage& image, int quality,
                                const CancellationToken& cancel) {
  OIIO::ImageSpec spec(int(image.width), int(image.height), 3, OIIO::TypeDesc::UINT8);
  spec.attribute("Compression", "jpeg:" + std::to_string(quality));
  return writeWithOpenImageIO(spec, OIIO::TypeDesc::UINT8, image.rgba.data(), FrameFormat::kJpeg,
                              cancel, 4, OIIO::stride_t(4) * image.width);
}

std::vector<uint8_t> encodeExr(const FrameImage& image, const CancellationToken& cancel) {
  const bool withDepth = !image.depth.empty();
  const int channels = withDepth ? 5 : 4;
  OIIO::ImageSpec spec(int(image.width), int(image.height), channels, OIIO::TypeDesc::HALF);
  if (withDepth) {
    spec.channelnames = {"R", "G", "B", "A", "Z"};
    spec.channelformats = {OIIO::TypeDesc::HALF, OIIO::TypeDesc::HALF, OIIO::TypeDesc::HALF,
                           OIIO::TypeDesc::HALF, OIIO::TypeDesc::FLOAT};
    spec.z_channel = 4;
  }
  spec.attribute("compression", "zip");
  // One float buffer in; OpenImageIO converts each channel to its own format.
  const size_t pixels = size_t(image.width) * image.height;
  std::vector<float> values(pixels * size_t(channels));
  for (size_t i = 0; i < pixels; ++i) {
    if (i % (size_t(kRowsPerPoll) * image.width) == 0) cancel.throwIfCancelled();
    for (size_t c = 0; c < 4; ++c) values[i * channels + c] = float(image.rgba[4 * i + c]) / 255.0f;
    if (withDepth) values[i * channels + 4] = image.depth[i];
  }
  return writeWithOpenImageIO(spec, OIIO::TypeDesc::FLOAT, values.data(), FrameFormat::kExr,
                              cancel);
}

#endif

}  // namespace

std::vector<uint8_t> encodeFrame(const FrameImage& image, const EncodingSettings& settings,
                                 [[maybe_unused]] const CancellationToken& cancel) {
  checkBuffers(image);
  if (settings.format == FrameFormat::kRawRgba) {
    return std::vector<uint8_t>(image.rgba.begin(), image.rgba.end());
  }
#if TESSERA_WITH_RENDER
  switch (settings.format) {
    case FrameFormat::kJpeg:
      return encodeJpeg(image, settings.jpegQuality, cancel);
    case FrameFormat::kExr:
      return encodeExr(image, cancel);
    default:
      return encodePng(image, cancel);
  }
#else
  throw RenderUnavailable(std::string("this server was built without OpenImageIO and cannot "
                                      "encode ") +
                          formatName(settings.format));
#endif
}

const char* formatName(FrameFormat format) {
  switch (format) {
    case FrameFormat::kPng:
      return "png";
    case FrameFormat::kJpeg:
      return "jpeg";
    case FrameFormat::kExr:
      return "exr";
    case FrameFormat::kRawRgba:
      return "raw";
  }
  return "unknown";
}

}  // namespace tessera::server
