// The seam between RenderService and the renderer, shaped like tessellation_engine.h: the service
// checks a request, admits it and loads the mesh, then asks a RenderBackend for one frame per
// camera and encodes it (frame_encoder.h). Everything gRPC stays in the service, so a backend is
// plain C++ over core/ and gpu/.
//
// render_backend_factory.h makes the backend this build has.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/mesh/control_mesh.h"
#include "core/request/accuracy.h"
#include "core/request/camera.h"
#include "server/calls/cancellation.h"
#include "server/calls/memory_reservation.h"
#include "server/meshes/patch_set_cache.h"
#include "server/tessellation/tessellation_engine.h"

namespace tessera::server {

// How every frame of a request is made; checked by render_request.h. A pixel accuracy is for
// each frame's own camera.
struct FrameSettings {
  Accuracy accuracy = Accuracy::pixel(0.5);
  double eta = 0.5;
  int64_t maxTriangles = 0;
  bool crackFilling = true;
};

// One frame to draw. The camera has been checked (render_request.h: core's validateCamera and
// sides up to 8192).
struct FrameJob {
  std::string meshId;
  std::string meshSha256;  // of its canonical content: the key of cached patch sets
  FrameSettings settings;
  Camera camera;
  // Where the frame reserves memory beyond its pixels (preprocessing, the triangles it draws);
  // null: nowhere.
  MemoryReservation* memory = nullptr;
};

struct FrameStageTimes {
  double waitMs = 0;  // for the device
  double planMs = 0;  // patch set (when not cached), plan, frustum test, splitting
  double tessellationMs = 0;
  double rasterShadingMs = 0;
  double crackFillingMs = 0;
  double renderMs = 0;  // the renderer's whole call
  bool gpuTimestamps = false;
};

struct FrameCounts {
  int64_t triangles = 0;
  int64_t pieces = 0;
  int64_t visiblePieces = 0;
  int64_t renderPatches = 0;
  int rings = 0;
  double averageRingDepth = 0;
  int maxRingDepth = 0;
  double guaranteedBound = 0;
};

// A frame as read back: rows top to bottom.
struct RenderedFrame {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<uint8_t> rgba;  // 4 bytes per pixel
  std::vector<float> depth;   // window depth per pixel, 1 = background
  FrameStageTimes times;
  FrameCounts counts;
  std::string device;
};

// This build or machine cannot render at all; the service answers UNIMPLEMENTED with the message.
class RenderUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The device could not take this frame (too many patches for its buffers, ...); the service
// answers RESOURCE_EXHAUSTED with the message.
class RenderLimitExceeded : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class RenderBackend {
 public:
  virtual ~RenderBackend() = default;

  // For GetServerInfo: a backend name ("vulkan"), whether frames can be made, and the device
  // (or why there is none).
  virtual std::string name() const = 0;
  virtual bool available() const = 0;
  virtual std::string detail() const = 0;
  virtual std::string device() const = 0;
  // What drawing a width x height frame holds in memory for its pixels (images, readback, the
  // returned buffers), before the triangles it draws: reserved before the frame is admitted.
  virtual int64_t frameBytes(int width, int height) const = 0;

  // Draws job's camera of mesh (validated). Called concurrently; implementations
  // serialize device access themselves. Polls cancel in every stage (planning, each device
  // submission, the copy out) and while waiting for the device (OperationCancelled). Throws
  // TesseraError for bad or unsupported input and exceeded budgets, RenderUnavailable,
  // RenderLimitExceeded, or another std::exception for failures.
  virtual RenderedFrame render(const ControlMesh& mesh, const FrameJob& job,
                               const CancellationToken& cancel) = 0;
};

}  // namespace tessera::server
