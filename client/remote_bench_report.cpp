#include "client/remote_bench_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "client/remote_progress.h"

namespace tessera::cli {
namespace {

constexpr const char* kRowFormat =
    "{:>12} {:<11} {:>9} {:>7} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>10} {:>10}\n";

void add(OperationStats& stats, const Sample& sample) {
  ++stats.requests;
  if (sample.outcome.ok()) {
    ++stats.ok;
  } else {
    ++stats.errors[sample.outcome.errorName()];
  }
  stats.bytesSent += sample.outcome.bytesSent;
  stats.bytesReceived += sample.outcome.bytesReceived;
}

LatencySummary summarizeLatency(std::vector<double> seconds) {
  LatencySummary s;
  if (seconds.empty()) return s;
  std::sort(seconds.begin(), seconds.end());
  s.count = static_cast<int64_t>(seconds.size());
  double sum = 0;
  for (double v : seconds) sum += v;
  s.mean = sum / double(seconds.size());
  s.p50 = percentile(seconds, 0.50);
  s.p90 = percentile(seconds, 0.90);
  s.p95 = percentile(seconds, 0.95);
  s.p99 = percentile(seconds, 0.99);
  s.max = seconds.back();
  return s;
}

std::string milliseconds(const LatencySummary& s, double value) {
  return s.count > 0 ? fmt::format("{:.2f}", value * 1e3) : "-";
}

std::string levelLabel(const LoadLevel& level) {
  if (level.rate) return fmt::format("{:g}/s", *level.rate);
  return std::to_string(level.workers);
}

void printRow(std::ostream& out, const std::string& label, std::string_view op,
              const OperationStats& s, double seconds) {
  const LatencySummary& l = s.latency;
  out << fmt::format(kRowFormat, label, op, s.requests, s.requests - s.ok,
                     fmt::format("{:.1f}", seconds > 0 ? double(s.requests) / seconds : 0.0),
                     fmt::format("{:.1f}", seconds > 0 ? double(s.ok) / seconds : 0.0),
                     milliseconds(l, l.p50), milliseconds(l, l.p90), milliseconds(l, l.p95),
                     milliseconds(l, l.p99), milliseconds(l, l.max), humanBytes(s.bytesSent),
                     humanBytes(s.bytesReceived));
}

nlohmann::json toJson(const LatencySummary& l) {
  if (l.count == 0) return nullptr;
  auto ms = [](double v) { return std::round(v * 1e6) / 1e3; };  // to the microsecond
  return {{"count", l.count}, {"mean", ms(l.mean)}, {"p50", ms(l.p50)}, {"p90", ms(l.p90)},
          {"p95", ms(l.p95)}, {"p99", ms(l.p99)},   {"max", ms(l.max)}};
}

nlohmann::json toJson(const OperationStats& s, double seconds) {
  nlohmann::json json = {{"requests", s.requests},
                         {"ok", s.ok},
                         {"errors", s.errors},
                         {"throughput_rps", seconds > 0 ? double(s.requests) / seconds : 0.0},
                         {"ok_rps", seconds > 0 ? double(s.ok) / seconds : 0.0},
                         {"latency_ms", toJson(s.latency)},
                         {"bytes_sent", s.bytesSent},
                         {"bytes_received", s.bytesReceived}};
  if (s.serverCompute.count > 0) json["server_compute_ms"] = toJson(s.serverCompute);
  return json;
}

}  // namespace

double percentile(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) return 0;
  const double rank = std::ceil(p * double(sorted.size()));
  const size_t index = static_cast<size_t>(std::clamp(rank, 1.0, double(sorted.size()))) - 1;
  return sorted[index];
}

LevelResult summarizeLevel(const LoadLevel& level, const PhaseResult& phase) {
  LevelResult result;
  result.level = level;
  result.seconds = phase.seconds;
  std::vector<double> all;
  std::map<BenchOp, std::vector<double>> byOperation, serverByOperation;
  for (const Sample& sample : phase.samples) {
    add(result.all, sample);
    add(result.byOperation[sample.op], sample);
    if (sample.outcome.ok()) {
      all.push_back(sample.latencySeconds);
      byOperation[sample.op].push_back(sample.latencySeconds);
      if (sample.outcome.serverSeconds >= 0) {
        serverByOperation[sample.op].push_back(sample.outcome.serverSeconds);
      }
    }
  }
  result.all.latency = summarizeLatency(std::move(all));
  for (auto& [op, seconds] : byOperation) {
    result.byOperation[op].latency = summarizeLatency(std::move(seconds));
  }
  for (auto& [op, seconds] : serverByOperation) {
    result.byOperation[op].serverCompute = summarizeLatency(std::move(seconds));
  }
  return result;
}

void printTableHeader(std::ostream& out, bool rateMode) {
  out << fmt::format(kRowFormat, rateMode ? "RATE" : "CONCURRENCY", "OPERATION", "REQUESTS",
                     "ERRORS", "REQ/S", "OK/S", "P50 MS", "P90 MS", "P95 MS", "P99 MS", "MAX MS", "SENT",
                     "RECEIVED");
}

void printLevel(std::ostream& out, const LevelResult& result, bool perOperation) {
  printRow(out, levelLabel(result.level), "all", result.all, result.seconds);
  if (perOperation) {
    for (const auto& [op, stats] : result.byOperation) {
      printRow(out, "", benchOpName(op), stats, result.seconds);
    }
  }
  if (!result.all.errors.empty()) {
    std::string list;
    for (const auto& [code, count] : result.all.errors) {
      list += fmt::format("{}{} {}", list.empty() ? "" : ", ", code, count);
    }
    out << fmt::format("{:>12} errors: {}\n", "", list);
  }
  out.flush();
}

nlohmann::json toJson(const LevelResult& result) {
  nlohmann::json level = toJson(result.all, result.seconds);
  level["concurrency"] = result.level.workers;
  level["rate_rps"] = result.level.rate ? nlohmann::json(*result.level.rate) : nullptr;
  level["seconds"] = result.seconds;
  nlohmann::json operations = nlohmann::json::object();
  for (const auto& [op, stats] : result.byOperation) {
    operations[std::string(benchOpName(op))] = toJson(stats, result.seconds);
  }
  level["operations"] = operations;
  return level;
}

}  // namespace tessera::cli
