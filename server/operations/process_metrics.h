// The process metrics every Prometheus client library exports (process_cpu_seconds_total,
// process_resident_memory_bytes, process_virtual_memory_bytes, process_start_time_seconds,
// process_open_fds, process_max_fds), read from /proc at scrape time, and tessera_build_info:
// what operators' standard dashboards and alerts expect of any server.
#pragma once

#include "server/operations/metrics.h"

namespace tessera::server {

void registerProcessMetrics(MetricsRegistry& registry);

}  // namespace tessera::server
