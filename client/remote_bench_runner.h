// How `tessera bench` applies load: a fixed number of workers, each sending its next request as
// soon as the previous one ends (closed loop, as ghz and perf_analyzer's concurrency mode do), or
// requests released at a fixed arrival rate (open loop) onto a bounded pool of workers. Every
// phase stops after a number of requests or a duration, whichever comes first, and every call has
// a deadline, so a phase always ends.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "client/remote_bench_calls.h"

namespace tessera::cli {

// One load level of a sweep.
struct LoadLevel {
  int workers = 1;             // concurrency; with a rate, the most requests in flight
  std::optional<double> rate;  // requests per second (open loop)
};

struct PhaseLimits {
  int64_t requests = 0;
  std::chrono::duration<double> duration{0};
};

struct Sample {
  BenchOp op;
  // Closed loop: from sending to the end of the call. Open loop: from the moment the request was
  // due, so that time spent waiting for a free worker counts (no coordinated omission).
  double latencySeconds;
  double endSeconds;  // when the call ended, from the start of the phase
  CallOutcome outcome;
};

using BenchClock = std::chrono::steady_clock;

// One call a request made, timed by the request itself.
struct TimedCall {
  BenchOp op;
  CallOutcome outcome;
  BenchClock::time_point sent, done;
};

// What request number i of a phase sends through a worker's client: one call for the mix, an
// upload and its first tessellation for the cold mix (remote_bench_cold.h).
using PhaseRequest = std::function<std::vector<TimedCall>(BenchClient& client, int64_t i)>;

struct PhaseResult {
  std::vector<Sample> samples;
  double seconds = 0;  // from the start of the phase to the end of its last call
};

// Runs requests 0, 1, ... of a phase; clients[w] serves worker w (at least level.workers of
// them). In open loop, a request's first call is timed from when the request was due.
PhaseResult runPhase(const std::vector<BenchClient*>& clients, const PhaseRequest& request,
                     const LoadLevel& level, const PhaseLimits& limits);

// The mix's requests: request i is one call of schedule[i % schedule.size()].
PhaseRequest mixRequests(const std::vector<BenchOp>& schedule);

// The mix as a repeating sequence in which every operation appears as often as its weight, spread
// out rather than in runs (smooth weighted round robin): {tessellate: 2, get: 1} gives t g t.
std::vector<BenchOp> interleaveMix(const std::vector<std::pair<BenchOp, int>>& weights);

}  // namespace tessera::cli
