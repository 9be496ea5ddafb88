// The gRPC service config of every channel the `tessera` CLI (and its load tester) opens:
// round_robin over every address the target resolves to (dns:///tessera-headless:50051 finds every
// ready pod of deploy/kubernetes; ipv4:127.0.0.1:50051,127.0.0.1:50052 lists servers) that reports
// SERVING (client-side health checking: a draining server leaves the rotation at once), and
// transparent retries of a call a server refused as UNAVAILABLE before answering (a replica that
// is draining or gone): up to 5 attempts, backing off from 0.1 s to 2 s. Other codes are never
// retried: RESOURCE_EXHAUSTED carries the server's own retry hint for the caller to honour.
#pragma once

namespace tessera::cli {

inline constexpr const char* kClientServiceConfig = R"json({
  "loadBalancingConfig": [{"round_robin": {}}],
  "healthCheckConfig": {"serviceName": ""},
  "methodConfig": [{
    "name": [{"service": "tessera.v1.MeshService"}, {"service": "tessera.v1.TessellationService"},
             {"service": "tessera.v1.RenderService"}, {"service": "tessera.v1.ServerInfoService"},
             {"service": "grpc.health.v1.Health"}],
    "retryPolicy": {
      "maxAttempts": 5,
      "initialBackoff": "0.1s",
      "maxBackoff": "2s",
      "backoffMultiplier": 2,
      "retryableStatusCodes": ["UNAVAILABLE"]
    }
  }]
})json";

}  // namespace tessera::cli
