// The seam between the service and the geometry: the server validates a Tessellate request,
// admits it, loads the mesh and then hands one TessellationJob to a TessellationEngine, which
// returns a GLB file and the numbers for the summary. Everything gRPC stays on the server side,
// so an engine is plain C++ over core/ (and gpu/) that tests can drive directly.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/mesh/control_mesh.h"
#include "core/output/glb_writer.h"
#include "core/request/accuracy.h"
#include "core/request/camera.h"
#include "server/calls/cancellation.h"
#include "server/calls/memory_reservation.h"

namespace tessera::server {

struct TessellationJob {
  std::string meshId;
  // SHA-256 of the mesh's canonical content: the key of what is derived from it (patch sets,
  // device surfaces), shared by identical content under any id and changed whenever a mesh is
  // deleted and re-uploaded with other content under the same id.
  std::string meshSha256;
  // Checked by tessellate_request.h: ε in model units (a relative tolerance already multiplied
  // by the mesh's diagonal, which the server's limits are checked against), pixels for `camera`,
  // or a uniform level.
  Accuracy accuracy;
  std::optional<Camera> camera;  // with a pixel accuracy only
  // Share of ε spent on ring refinement depth (the rest on the tessellation), in [0, 1).
  double eta = 0.5;
  // The engine refuses (TesseraError kLimitExceeded) to produce more triangles than this.
  int64_t maxTriangles = 0;
  GlbEncoding encoding = GlbEncoding::kFloat;
  // Where the job reserves memory as it learns its size (preprocessing, output); null: nowhere.
  MemoryReservation* memory = nullptr;
  // Progress of the whole job in [0, 1] under a short stage name ("refining", "tessellating",
  // "encoding"); may be empty. Call it from the thread that called run().
  std::function<void(std::string_view stage, double fraction)> reportProgress;
};

struct StageTime {
  std::string stage;
  double seconds = 0.0;
};

// What the server reports in tessera.v1.TessellationSummary (core's tessera::TessellationSummary
// is what the CPU engine computes it from).
struct TessellationSummary {
  int64_t triangles = 0;
  int64_t patches = 0;
  int64_t rings = 0;  // extraordinary rings refined by FAS
  double averageDepth = 0.0;
  int maxDepth = 0;
  double guaranteedBound = 0.0;  // proven distance bound to the limit surface, model units
  double tolerance = 0.0;        // ε the engine used (smallest per-piece ε in pixel mode; 0 for a uniform level)
  std::vector<StageTime> timings;
};

struct TessellationOutput {
  std::vector<uint8_t> glb;  // a complete GLB file
  TessellationSummary summary;
};

// Thrown by an engine that cannot tessellate at all in this build or on this machine; the
// server answers UNIMPLEMENTED with the message.
class TessellationUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class TessellationEngine {
 public:
  virtual ~TessellationEngine() = default;

  // Backend name for GetServerInfo ("cpu", "cuda", ...).
  virtual std::string name() const = 0;
  // Whether run() can produce results; false makes GetServerInfo say so.
  virtual bool available() const = 0;
  // Why it is unavailable, or what it runs on, for GetServerInfo.
  virtual std::string detail() const = 0;
  // The accelerator it runs on, one line (empty: the CPU only), for GetServerInfo and metrics.
  virtual std::string device() const { return {}; }

  // Whether a job on this content, down to `finestRelativeTolerance` (0: any; core's
  // finestRelativeTolerance), would find its preprocessing done: the server's sign of a cheap job
  // (job_cost.h). False when the engine cannot tell.
  virtual bool preprocessed(const std::string& /*meshSha256*/, double /*finestRelativeTolerance*/) const {
    return false;
  }

  // Tessellates mesh (already validated) as job asks. Polls cancel often enough to
  // stop within a fraction of a second and then throws OperationCancelled (core's
  // TessellationOptions::checkpoint can call cancel.throwIfCancelled()). Reports bad or
  // unsupported input and exceeded budgets by throwing TesseraError (the server maps the kind
  // to INVALID_ARGUMENT / UNIMPLEMENTED / RESOURCE_EXHAUSTED). Called concurrently from several
  // threads, up to the server's max concurrent jobs.
  virtual TessellationOutput run(const ControlMesh& mesh, const TessellationJob& job,
                                 const CancellationToken& cancel) = 0;
};

}  // namespace tessera::server
