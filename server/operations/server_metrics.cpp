#include "server/operations/server_metrics.h"

namespace tessera::server {

ServerMetrics::ServerMetrics(MetricsRegistry& registry)
    : requests(registry.counter("tessera_requests_total",
                                "RPCs finished, by full method name and gRPC status code.",
                                {"method", "code"})),
      latency(registry.histogram(
          "tessera_request_duration_seconds", "Time from an RPC's start to its status.",
          {"method"}, {0.001, 0.005, 0.01, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10, 30, 60, 300})),
      uploadBytes(registry.counter("tessera_upload_bytes_total",
                                   "Mesh data bytes received by UploadMesh.")),
      trianglesProduced(registry.counter("tessera_triangles_produced_total",
                                         "Triangles in tessellations delivered to clients.")),
      glbBytesSent(registry.counter("tessera_glb_bytes_sent_total",
                                    "GLB bytes streamed by Tessellate.")) {}

}  // namespace tessera::server
