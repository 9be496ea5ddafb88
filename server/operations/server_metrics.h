// The metrics Tessera's server exports, by name, so that handlers record them without knowing
// about the registry. Levels owned by other objects (cache, queue, store) are registered as
// sampled values where those objects are built (server_app.cpp).
#pragma once

#include "server/calls/call_notes.h"
#include "server/operations/metrics.h"

namespace tessera::server {

struct ServerMetrics {
  explicit ServerMetrics(MetricsRegistry& registry);

  CounterFamily& requests;         // {method, code}
  HistogramFamily& latency;        // {method}, seconds
  CounterFamily& uploadBytes;      // data bytes received in uploads
  CounterFamily& trianglesProduced;
  CounterFamily& glbBytesSent;
  // Not a metric: what handlers add to their call's log line (mesh, triangles, bytes).
  CallNotes notes;
};

}  // namespace tessera::server
