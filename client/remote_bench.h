// `tessera bench`: a load tester for tessera-server in the manner of ghz and perf_analyzer.
//
//   tessera --server H:P bench [--mix tessellate=8,get=1,list=1,info=1] [--mesh meshes/NAME ...]
//       [--tolerance E [--relative] | --level P] [--concurrency 1,2,4,8,16,32 | --rate R/s]
//       [--requests N] [--duration 30s] [--warmup N] [--json out.json]
//   tessera --server H:P bench --cold N [--cold-seed S] --mesh meshes/NAME --tolerance E ... (as
//   above)
//
// Each level of a concurrency sweep runs that many workers in a closed loop; --rate releases
// requests at fixed times instead (open loop) onto --concurrency workers (default 32). A level
// ends after --requests or --duration, whichever comes first, and every call has a deadline
// (--timeout), so a run always ends. Per level it reports throughput offered (every request) and
// useful (the successful ones), p50/p90/p95/p99/max latency of the successful calls, request and
// response bytes (serialized protobuf messages, without HTTP/2 framing) and errors by gRPC status
// code. A closed-loop worker refused with a retry hint (grpc-retry-pushback-ms: the server is
// busy) waits 0.5–1.5 times the hint before its next request, as a well-behaved client does.
//
// --cold N replaces the mix with the cold path (remote_bench_cold.h): per level, N uploads of
// meshes the server has not seen, each tessellated once; the levels report the uploads' latency
// and the first GLB's (from sending the Tessellate until the whole GLB has arrived and checked).
//
// Channels: by default every worker has a channel, and so a TCP connection, of its own: N workers
// stand for N independent clients, which is what a server sees in production, and no worker
// waits on another's HTTP/2 connection (one connection's flow control and its single client-side
// poller would make the client the bottleneck). --shared-channel multiplexes all workers over one
// connection instead, as one process with many threads would.
//
// Exit codes: 0 when the run completed, even with failed calls (they are the measurement);
// kExitUsage for bad flags; kExitRemote when the server cannot be reached or refuses the setup
// calls (server info, the meshes named); kExitIo when --json cannot be written.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>

#include "client/commands.h"
#include "client/remote_connection.h"

namespace tessera::cli {

void registerBenchCommand(CLI::App& app, CommandContext& context,
                          std::shared_ptr<const RemoteEndpoint> endpoint);

}  // namespace tessera::cli
