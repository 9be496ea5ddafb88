// What `tessera bench` reports for each load level, as operators read it from ghz or
// perf_analyzer: throughput, latency percentiles, bytes moved and errors by status code, for all
// requests and per operation; as a table and as JSON.
#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "client/remote_bench_runner.h"

namespace tessera::cli {

// Over successful calls only: a fast refusal would otherwise pass for a fast answer.
struct LatencySummary {
  int64_t count = 0;
  double mean = 0, p50 = 0, p90 = 0, p95 = 0, p99 = 0, max = 0;  // seconds
};

struct OperationStats {
  int64_t requests = 0;
  int64_t ok = 0;
  std::map<std::string, int64_t> errors;  // by status code name (CallOutcome::errorName)
  LatencySummary latency;
  // Tessellate: the server's own compute time per successful call (CallOutcome::serverSeconds).
  LatencySummary serverCompute;
  int64_t bytesSent = 0;
  int64_t bytesReceived = 0;
};

struct LevelResult {
  LoadLevel level;
  double seconds = 0;  // the measured phase's wall time
  OperationStats all;
  std::map<BenchOp, OperationStats> byOperation;
  double throughput() const { return seconds > 0 ? double(all.requests) / seconds : 0; }
};

LevelResult summarizeLevel(const LoadLevel& level, const PhaseResult& phase);

// Nearest-rank percentile (p in (0, 1]) of values sorted in ascending order.
double percentile(const std::vector<double>& sorted, double p);

void printTableHeader(std::ostream& out, bool rateMode);
// One row for all requests and, with perOperation, one per operation of the mix; then the errors.
void printLevel(std::ostream& out, const LevelResult& result, bool perOperation);

nlohmann::json toJson(const LevelResult& result);

}  // namespace tessera::cli
