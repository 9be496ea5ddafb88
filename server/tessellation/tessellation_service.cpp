#include "server/tessellation/tessellation_service.h"

#include <algorithm>
#include <chrono>
#include <string_view>

#include "core/base/sha256.h"
#include "server/calls/call_guard.h"
#include "server/calls/memory_release.h"
#include "server/calls/status_error.h"
#include "server/meshes/mesh_names.h"

namespace tessera::server {
namespace {

namespace v1 = tessera::v1;

// The API's promise (tessellation.proto): no GlbChunk carries more than 64 KiB.
constexpr size_t kGlbChunkBytes = 64 * 1024;

using Writer = Watched<grpc::ServerWriter<v1::TessellateResponse>>;

// A failed write means the client is gone; nothing more can reach it.
void send(Writer& writer, const v1::TessellateResponse& message) {
  if (!writer.Write(message)) throw OperationCancelled();
}

void sendProgress(Writer& writer, std::string_view stage, double fraction) {
  v1::TessellateResponse message;
  message.mutable_progress()->set_stage(std::string(stage));
  message.mutable_progress()->set_fraction(std::clamp(fraction, 0.0, 1.0));
  send(writer, message);
}

// Forwards engine progress, thinned out: a blocking write while the job holds its admission slot
// must stay rare, and a client needs no more than a few updates a second.
class ProgressForwarder {
 public:
  explicit ProgressForwarder(Writer& writer) : writer_(writer) {}

  void operator()(std::string_view stage, double fraction) {
    auto now = std::chrono::steady_clock::now();
    bool newStage = stage != lastStage_;
    if (!newStage && fraction < lastFraction_ + kMinStep && now - lastSent_ < kMinInterval) return;
    sendProgress(writer_, stage, fraction);
    lastStage_ = std::string(stage);
    lastFraction_ = fraction;
    lastSent_ = now;
  }

 private:
  static constexpr double kMinStep = 0.05;
  static constexpr auto kMinInterval = std::chrono::milliseconds(250);
  Writer& writer_;
  std::string lastStage_;
  double lastFraction_ = 0.0;
  std::chrono::steady_clock::time_point lastSent_;
};

void sendGlb(Writer& writer, const std::vector<uint8_t>& glb, const CancellationToken& cancel) {
  for (size_t offset = 0; offset < glb.size(); offset += kGlbChunkBytes) {
    cancel.throwIfCancelled();
    size_t size = std::min(kGlbChunkBytes, glb.size() - offset);
    v1::TessellateResponse message;
    message.mutable_glb_chunk()->set_offset(static_cast<int64_t>(offset));
    message.mutable_glb_chunk()->set_data(reinterpret_cast<const char*>(glb.data() + offset), size);
    send(writer, message);
  }
}

// The GLB's digest in 16 MiB slices, the call's cancellation checked between them (a file of
// hundreds of megabytes is a second of hashing).
void sendSummary(Writer& writer, const TessellationOutput& output, const CancellationToken& cancel) {
  v1::TessellateResponse message;
  v1::TessellationSummary* s = message.mutable_summary();
  const TessellationSummary& in = output.summary;
  s->set_triangles(in.triangles);
  s->set_patches(in.patches);
  s->set_rings(in.rings);
  s->set_average_depth(in.averageDepth);
  s->set_max_depth(in.maxDepth);
  s->set_guaranteed_bound(in.guaranteedBound);
  s->set_tolerance(in.tolerance);
  for (const StageTime& t : in.timings) {
    v1::StageTiming* timing = s->add_timings();
    timing->set_stage(t.stage);
    timing->set_seconds(t.seconds);
  }
  s->set_glb_size(static_cast<int64_t>(output.glb.size()));
  s->set_glb_sha256(sha256Hex(std::string_view(reinterpret_cast<const char*>(output.glb.data()), output.glb.size()),
                               [&cancel] { cancel.throwIfCancelled(); }));
  send(writer, message);
}

}  // namespace

AdmissionLane TessellationServiceImpl::laneFor(const TessellationJob& job, const JobShape& shape) const {
  if (!engine_.preprocessed(job.meshSha256, shape.uniform ? 0 : shape.relativeTolerance)) return AdmissionLane::kMain;
  const std::optional<double> triangles = costs_.estimate(job.meshSha256, shape);
  return triangles && *triangles <= double(lightJobTriangles_) ? AdmissionLane::kLight : AdmissionLane::kMain;
}

grpc::Status TessellationServiceImpl::Tessellate(grpc::ServerContext* context,
                                                 const v1::TessellateRequest* request,
                                                 grpc::ServerWriter<v1::TessellateResponse>* stream) {
  const ReleaseMemoryOnExit release;  // after the call, whichever way it ends
  return guardCall(*context, auth_, [&] {
    TessellationJob job = checkTessellateRequest(*request, limits_);
    StreamWatch::Call call = streams_.open(*context, "Tessellate");
    Writer watched(*stream, call);
    Writer* writer = &watched;
    std::string id = meshIdFromName(request->name(), "name");
    MeshMetadata metadata = repository_.metadata(id);
    placeOnMesh(job, metadata, limits_);
    CancellationToken cancel = cancellationFor(*context);
    // The mesh before admission (almost always the decoded copy the repository keeps): a camera
    // that asks too much is refused without queueing, and the job's shape picks its lane.
    sendProgress(*writer, "loading", 0.0);
    std::shared_ptr<const ControlMesh> mesh = repository_.mesh(metadata);
    checkOnMesh(job, *mesh, limits_);
    const JobShape shape = shapeOf(*mesh, job);
    TessellationOutput output;
    {
      // The slot covers the computation only: streaming the result is I/O and must not keep the
      // next job from computing.
      AdmissionControl::Slot slot = admission_.acquire(
          cancel, [&](int) { sendProgress(*writer, "queued", 0.0); }, 0, "the job", laneFor(job, shape));
      job.memory = &slot;
      ProgressForwarder forward(*writer);
      job.reportProgress = [&](std::string_view stage, double fraction) { forward(stage, fraction); };
      try {
        output = engine_.run(*mesh, job, cancel);
      } catch (const TessellationUnavailable& error) {
        throwStatus(grpc::StatusCode::UNIMPLEMENTED, error.what());
      }
    }
    costs_.record(job.meshSha256, shape, output.summary.triangles);
    sendGlb(*writer, output.glb, cancel);
    sendSummary(*writer, output, cancel);
    metrics_.trianglesProduced.add({}, static_cast<double>(output.summary.triangles));
    metrics_.glbBytesSent.add({}, static_cast<double>(output.glb.size()));
    metrics_.notes.note(context, "mesh", id);
    metrics_.notes.note(context, "triangles", int64_t(output.summary.triangles));
    metrics_.notes.note(context, "bytes", int64_t(output.glb.size()));
  });
}

}  // namespace tessera::server
