// tessera.v1.TessellationService: everything around the engine. Validates the request, finds the
// mesh, waits for admission in the lane its estimated cost picks (job_cost.h), runs the engine with the call's cancellation, and streams the GLB in
// 64 KiB chunks followed by a summary with its checksum.
#pragma once

#include "server/calls/admission_control.h"
#include "server/calls/bearer_auth.h"
#include "server/meshes/mesh_repository.h"
#include "server/operations/server_metrics.h"
#include "server/calls/stream_watch.h"
#include "server/tessellation/job_cost.h"
#include "server/tessellation/tessellate_request.h"
#include "server/tessellation/tessellation_engine.h"
#include "tessera/v1/tessellation.grpc.pb.h"

namespace tessera::server {

class TessellationServiceImpl final : public tessera::v1::TessellationService::Service {
 public:
  TessellationServiceImpl(MeshRepository& repository, AdmissionControl& admission, StreamWatch& streams,
                          TessellationEngine& engine, const BearerAuth& auth,
                          const TessellationLimits& limits, ServerMetrics& metrics,
                          int64_t lightJobTriangles = 0)
      : repository_(repository), admission_(admission), streams_(streams), engine_(engine), auth_(auth),
        limits_(limits), metrics_(metrics), lightJobTriangles_(lightJobTriangles) {}

  grpc::Status Tessellate(grpc::ServerContext* context,
                          const tessera::v1::TessellateRequest* request,
                          grpc::ServerWriter<tessera::v1::TessellateResponse>* writer) override;

 private:
  // The light lane for a job on a preprocessed mesh estimated at most lightJobTriangles_
  // (job_cost.h); the main lane otherwise.
  AdmissionLane laneFor(const TessellationJob& job, const JobShape& shape) const;

  MeshRepository& repository_;
  AdmissionControl& admission_;
  StreamWatch& streams_;
  TessellationEngine& engine_;
  const BearerAuth& auth_;
  const TessellationLimits limits_;
  ServerMetrics& metrics_;
  const int64_t lightJobTriangles_;
  TessellationCosts costs_;
};

}  // namespace tessera::server
