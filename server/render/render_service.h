// tessera.v1.RenderService (render.proto): everything around the render backend. Checks the
// request (render_request.h), finds the mesh, and per frame waits for admission (the same
// AdmissionControl as tessellations), has the backend draw it, encodes it (frame_encoder.h),
// and streams a header and 64 KiB chunks. RenderSession adds a reader thread that keeps only
// the newest camera (render_session.h).
#pragma once

#include <memory>

#include "server/calls/admission_control.h"
#include "server/calls/bearer_auth.h"
#include "server/render/frame_encoder.h"
#include "server/meshes/mesh_repository.h"
#include "server/operations/metrics.h"
#include "server/render/render_backend.h"
#include "server/calls/stream_watch.h"
#include "server/calls/accuracy_limits.h"
#include "tessera/v1/render.grpc.pb.h"

namespace tessera::server {

class RenderServiceImpl final : public tessera::v1::RenderService::Service {
 public:
  RenderServiceImpl(MeshRepository& repository, AdmissionControl& admission, StreamWatch& streams, RenderBackend& backend,
                    const BearerAuth& auth, const TessellationLimits& limits,
                    MetricsRegistry& registry);

  grpc::Status Render(grpc::ServerContext* context, const tessera::v1::RenderRequest* request,
                      grpc::ServerWriter<tessera::v1::RenderResponse>* writer) override;

  grpc::Status RenderSession(
      grpc::ServerContext* context,
      grpc::ServerReaderWriter<tessera::v1::SessionResponse, tessera::v1::SessionRequest>* stream)
      override;

 private:
  struct EncodedFrame;
  class MeshHandle;

  // One frame, admitted, drawn and encoded; the admission slot is let go before it returns, so
  // streaming the bytes never holds up the next job.
  EncodedFrame makeFrame(MeshHandle& mesh, const FrameJob& job, const EncodingSettings& encoding,
                         const CancellationToken& cancel);
  void requireBackend() const;

  MeshRepository& repository_;
  AdmissionControl& admission_;
  StreamWatch& streams_;
  RenderBackend& backend_;
  const BearerAuth& auth_;
  const TessellationLimits limits_;
  CounterFamily& framesRendered_;  // {method, format}
  CounterFamily& imageBytesSent_;  // {method}
  CounterFamily& camerasDropped_;  // stale session cameras never drawn
};

}  // namespace tessera::server
