#include "server/render/render_service.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <vector>

#include "core/base/error.h"
#include "server/calls/accuracy_limits.h"
#include "server/calls/call_guard.h"
#include "server/calls/memory_release.h"
#include "server/calls/status_error.h"
#include "server/meshes/mesh_names.h"
#include "server/render/frame_digest.h"
#include "server/render/render_request.h"
#include "server/render/render_session.h"

namespace tessera::server {

namespace v1 = tessera::v1;

namespace {

// The API's promise (render.proto): no ImageChunk carries more than 64 KiB.
constexpr size_t kImageChunkBytes = 64 * 1024;

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The service's own share of a frame: the encoded image and the message that carries it.
constexpr int64_t kEncodingBytesPerPixel = 8;

void fillHeader(const RenderedFrame& frame, FrameFormat format, double admissionMs, double encodeMs,
                v1::FrameHeader& header) {
  header.set_width(int32_t(frame.width));
  header.set_height(int32_t(frame.height));
  header.set_format(toProto(format));
  header.set_device(frame.device);
  v1::FrameTimings* t = header.mutable_timings();
  t->set_wait_ms(admissionMs + frame.times.waitMs);
  t->set_plan_ms(frame.times.planMs);
  t->set_tessellation_ms(frame.times.tessellationMs);
  t->set_raster_shading_ms(frame.times.rasterShadingMs);
  t->set_crack_filling_ms(frame.times.crackFillingMs);
  t->set_render_ms(frame.times.renderMs);
  t->set_encode_ms(encodeMs);
  t->set_gpu_timestamps(frame.times.gpuTimestamps);
  v1::FrameStatistics* s = header.mutable_statistics();
  const FrameCounts& c = frame.counts;
  s->set_triangles(c.triangles);
  s->set_pieces(c.pieces);
  s->set_visible_pieces(c.visiblePieces);
  s->set_render_patches(c.renderPatches);
  s->set_rings(c.rings);
  s->set_average_ring_depth(c.averageRingDepth);
  s->set_max_ring_depth(c.maxRingDepth);
  s->set_guaranteed_bound(c.guaranteedBound);
}

// A failed write means the client is gone; nothing more can reach it.
template <typename Stream, typename Message>
void send(Stream& stream, const Message& message) {
  if (!stream.Write(message)) throw OperationCancelled();
}

// `where` ("cameras[2]") prefixed to a frame's error, so that the client knows which camera.
[[noreturn]] void rethrowFor(const std::string& where) {
  try {
    throw;
  } catch (const TesseraError& error) {
    throw TesseraError(error.kind(), where + ": " + error.what());
  } catch (const RenderLimitExceeded& error) {
    throwResourceExhausted(where + ": " + error.what());
  } catch (const RenderUnavailable& error) {
    throwStatus(grpc::StatusCode::UNIMPLEMENTED, error.what());
  }
}

// The status a session reports in-band for a camera it could not draw (call_guard.cpp's
// mapping, for the exceptions a frame can end in).
v1::FrameError frameError(uint64_t sequence) {
  v1::FrameError out;
  out.set_sequence(sequence);
  grpc::Status status;
  try {
    throw;
  } catch (const StatusError& error) {
    status = error.status();
  } catch (const TesseraError& error) {
    status = statusFromTesseraError(error);
  } catch (const RenderLimitExceeded& error) {
    status = {grpc::StatusCode::RESOURCE_EXHAUSTED, error.what()};
  } catch (const RenderUnavailable& error) {
    status = {grpc::StatusCode::UNIMPLEMENTED, error.what()};
  } catch (const std::bad_alloc&) {
    status = {grpc::StatusCode::RESOURCE_EXHAUSTED, "the server ran out of memory for this frame"};
  } catch (const std::exception& error) {
    spdlog::error("session frame {}: internal error: {}", sequence, error.what());
    status = {grpc::StatusCode::INTERNAL, "internal error; the server's log has the cause"};
  } catch (...) {
    spdlog::error("session frame {}: internal error: unknown exception", sequence);
    status = {grpc::StatusCode::INTERNAL, "internal error"};
  }
  out.set_code(int32_t(status.error_code()));
  out.set_message(status.error_message());
  return out;
}

}  // namespace

struct RenderServiceImpl::EncodedFrame {
  v1::FrameHeader header;
  std::vector<uint8_t> bytes;
};

// The mesh of a call, loaded (from the repository's cache or the store) the first time a frame
// needs it, inside that frame's admission slot, and kept for the rest of the call.
class RenderServiceImpl::MeshHandle {
 public:
  MeshHandle(MeshRepository& repository, MeshMetadata metadata)
      : repository_(repository), metadata_(std::move(metadata)) {}
  const ControlMesh& get() {
    if (!mesh_) mesh_ = repository_.mesh(metadata_);
    return *mesh_;
  }

 private:
  MeshRepository& repository_;
  const MeshMetadata metadata_;
  std::shared_ptr<const ControlMesh> mesh_;
};

namespace {

// Streams an encoded frame: its header, then chunks of at most 64 KiB.
template <typename Response, typename Stream>
void sendFrame(Stream& stream, const v1::FrameHeader& header, const std::vector<uint8_t>& bytes,
               const CancellationToken& cancel) {
  Response headerMessage;
  *headerMessage.mutable_header() = header;
  send(stream, headerMessage);
  for (size_t offset = 0; offset < bytes.size(); offset += kImageChunkBytes) {
    cancel.throwIfCancelled();
    size_t size = std::min(kImageChunkBytes, bytes.size() - offset);
    Response chunk;
    chunk.mutable_chunk()->set_offset(int64_t(offset));
    chunk.mutable_chunk()->set_data(reinterpret_cast<const char*>(bytes.data() + offset), size);
    send(stream, chunk);
  }
}

// Joins the session's reader thread on every way out. If the call ends while the client still
// streams (a failed write, cancellation), the reader is blocked in Read(): cancelling the call is
// the one way to wake it, and the client is gone or leaving anyway.
class ReaderThread {
 public:
  ReaderThread(grpc::ServerContext& context, const LatestCameraMailbox& mailbox, std::thread thread)
      : context_(context), mailbox_(mailbox), thread_(std::move(thread)) {}
  ~ReaderThread() {
    if (!thread_.joinable()) return;
    if (!mailbox_.finished()) context_.TryCancel();
    thread_.join();
  }
  void join() { thread_.join(); }

 private:
  grpc::ServerContext& context_;
  const LatestCameraMailbox& mailbox_;
  std::thread thread_;
};

// Records a session's counts when it ends, whichever way.
struct SessionLog {
  CounterFamily& dropped;
  const LatestCameraMailbox& mailbox;
  const std::string& meshId;
  const uint64_t& frames;
  const uint64_t& failed;
  ~SessionLog() {
    dropped.add({}, double(mailbox.dropped()));
    spdlog::debug("render session on {}: {} cameras, {} frames, {} failed, {} dropped", meshId,
                  mailbox.received(), frames, failed, mailbox.dropped());
  }
};

}  // namespace

RenderServiceImpl::RenderServiceImpl(MeshRepository& repository, AdmissionControl& admission,
                                     StreamWatch& streams, RenderBackend& backend, const BearerAuth& auth,
                                     const TessellationLimits& limits, MetricsRegistry& registry)
    : repository_(repository),
      admission_(admission),
      streams_(streams),
      backend_(backend),
      auth_(auth),
      limits_(limits),
      framesRendered_(registry.counter("tessera_frames_rendered_total",
                                       "Frames rendered and sent, by RPC and image format.",
                                       {"method", "format"})),
      imageBytesSent_(registry.counter("tessera_image_bytes_sent_total",
                                       "Encoded image bytes streamed by RenderService.",
                                       {"method"})),
      camerasDropped_(registry.counter("tessera_session_cameras_dropped_total",
                                       "RenderSession camera updates replaced by a newer one "
                                       "before they were drawn.")) {}

void RenderServiceImpl::requireBackend() const {
  if (!backend_.available()) throwStatus(grpc::StatusCode::UNIMPLEMENTED, backend_.detail());
}

RenderServiceImpl::EncodedFrame RenderServiceImpl::makeFrame(MeshHandle& mesh, const FrameJob& job,
                                                             const EncodingSettings& encoding,
                                                             const CancellationToken& cancel) {
  EncodedFrame out;
  Clock::time_point queued = Clock::now();
  const int width = job.camera.width, height = job.camera.height;
  // The pixels are known up front: the frame waits until they fit, or is refused at once.
  const int64_t pixelBytes =
      backend_.frameBytes(width, height) + kEncodingBytesPerPixel * int64_t(width) * int64_t(height);
  AdmissionControl::Slot slot =
      admission_.acquire(cancel, {}, pixelBytes, fmt::format("a {} x {} frame", width, height));
  double admissionMs = millisecondsSince(queued);
  FrameJob reserving = job;
  reserving.memory = &slot;
  RenderedFrame frame = backend_.render(mesh.get(), reserving, cancel);
  cancel.throwIfCancelled();
  Clock::time_point encodeStart = Clock::now();
  if (encoding.format == FrameFormat::kRawRgba) {
    out.bytes = std::move(frame.rgba);  // the raw format is the buffer itself: no copy
  } else {
    out.bytes =
        encodeFrame(FrameImage{frame.width, frame.height, frame.rgba, frame.depth}, encoding, cancel);
    cancel.throwIfCancelled();
  }
  fillHeader(frame, encoding.format, admissionMs, millisecondsSince(encodeStart), out.header);
  out.header.set_image_bytes(int64_t(out.bytes.size()));
  out.header.set_image_sha256(frameSha256Hex(out.bytes, cancel));
  return out;
}

grpc::Status RenderServiceImpl::Render(grpc::ServerContext* context,
                                       const v1::RenderRequest* request,
                                       grpc::ServerWriter<v1::RenderResponse>* writer) {
  const ReleaseMemoryOnExit release;  // the frames' buffers, after the call
  return guardCall(*context, auth_, [&] {
    requireBackend();
    std::string id = meshIdFromName(request->name(), "name");
    CheckedRenderSettings settings = checkRenderSettings(request->settings(), "settings", limits_);
    const int count = request->cameras_size();
    if (count == 0) throwInvalidArgument("cameras: at least one camera is required");
    if (count > kMaxCamerasPerRequest) {
      throwInvalidArgument(
          fmt::format("cameras: at most {} per request (got {})", kMaxCamerasPerRequest, count));
    }
    // Every camera is checked before the first frame: a bad one costs the client no frames.
    std::vector<Camera> cameras;
    for (int i = 0; i < count; ++i) {
      cameras.push_back(checkRenderCamera(request->cameras(i), fmt::format("cameras[{}]", i),
                                          settings.frame, limits_));
    }
    MeshMetadata metadata = repository_.metadata(id);
    checkSettingsForMesh(settings.frame, "settings", metadata, limits_);
    CancellationToken cancel = cancellationFor(*context);
    StreamWatch::Call call = streams_.open(*context, "Render");
    Watched watched(*writer, call);
    MeshHandle mesh(repository_, metadata);
    if (settings.frame.accuracy.pixelAccurate()) {
      // Pixels hold to the same floor as a tolerance, at each camera: every camera before any frame.
      for (int i = 0; i < count; ++i) {
        checkPixelsOnMesh(settings.frame.accuracy, cameras[size_t(i)], mesh.get(), fmt::format("cameras[{}]", i),
                          limits_);
      }
    }
    const char* format = formatName(settings.encoding.format);
    for (int i = 0; i < count; ++i) {
      cancel.throwIfCancelled();
      FrameJob job{metadata.id, metadata.sha256, settings.frame, cameras[size_t(i)]};
      EncodedFrame frame;
      try {
        frame = makeFrame(mesh, job, settings.encoding, cancel);
      } catch (const OperationCancelled&) {
        throw;
      } catch (const StatusError&) {
        throw;
      } catch (...) {
        rethrowFor(fmt::format("cameras[{}]", i));
      }
      frame.header.set_index(i);
      sendFrame<v1::RenderResponse>(watched, frame.header, frame.bytes, cancel);
      framesRendered_.add({"Render", format});
      imageBytesSent_.add({"Render"}, double(frame.bytes.size()));
    }
  });
}

grpc::Status RenderServiceImpl::RenderSession(grpc::ServerContext* context, SessionStream* stream) {
  const ReleaseMemoryOnExit release;  // the frames' buffers, after the session
  return guardCall(*context, auth_, [&] {
    requireBackend();
    StreamWatch::Call call = streams_.open(*context, "RenderSession", /*session=*/true);
    Watched watched(*stream, call);
    v1::SessionRequest first;
    if (!watched.Read(&first)) {
      throwInvalidArgument("start: the stream ended before its first message (a SessionStart)");
    }
    if (!first.has_start()) throwInvalidArgument("start: the first message must be a SessionStart");
    const v1::SessionStart& start = first.start();
    std::string id = meshIdFromName(start.name(), "start.name");
    CheckedRenderSettings settings =
        checkRenderSettings(start.settings(), "start.settings", limits_);
    MeshMetadata metadata = repository_.metadata(id);
    checkSettingsForMesh(settings.frame, "start.settings", metadata, limits_);
    CancellationToken cancel = cancellationFor(*context);
    MeshHandle mesh(repository_, metadata);
    const char* format = formatName(settings.encoding.format);

    LatestCameraMailbox mailbox;
    uint64_t frames = 0, failed = 0;
    // Counted however the session ends (interactive clients usually just hang up), after the
    // reader has been joined.
    SessionLog log{camerasDropped_, mailbox, metadata.id, frames, failed};
    ReaderThread reader(*context, mailbox, std::thread([&] {
      readCameraUpdates(watched, settings.frame, limits_, mailbox);
    }));
    while (std::optional<PendingCamera> next = mailbox.next(cancel)) {
      FrameJob job{metadata.id, metadata.sha256, settings.frame, next->camera};
      EncodedFrame frame;
      try {
        // The floor Render checks for every camera first, here as each camera comes.
        checkPixelsOnMesh(settings.frame.accuracy, next->camera, mesh.get(), "camera", limits_);
        frame = makeFrame(mesh, job, settings.encoding, cancel);
      } catch (const OperationCancelled&) {
        throw;
      } catch (...) {
        // The session goes on: the next camera may well be drawable.
        v1::SessionResponse message;
        *message.mutable_error() = frameError(next->sequence);
        send(watched, message);
        ++failed;
        continue;
      }
      frame.header.set_sequence(next->sequence);
      sendFrame<v1::SessionResponse>(watched, frame.header, frame.bytes, cancel);
      framesRendered_.add({"RenderSession", format});
      imageBytesSent_.add({"RenderSession"}, double(frame.bytes.size()));
      ++frames;
    }
    reader.join();
    if (std::optional<StatusError> error = mailbox.failure()) throw *error;
  });
}

}  // namespace tessera::server
