#include "client/remote_bench_runner.h"

#include <algorithm>
#include <atomic>
#include <optional>
#include <random>
#include <thread>

namespace tessera::cli {
namespace {

using Clock = BenchClock;

double secondsBetween(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

// One worker's loop: claims request numbers from next until the phase's count or time runs out.
// Closed-loop workers honour a busy server's retry hint, waiting 0.5–1.5 times it (jittered, so
// that refused workers do not come back together) before their next request; at a fixed rate
// the schedule is the load offered, and it is kept.
std::vector<Sample> work(BenchClient& client, const PhaseRequest& request, const LoadLevel& level,
                         const PhaseLimits& limits, Clock::time_point start,
                         std::atomic<int64_t>& next, unsigned seed) {
  std::minstd_rand jitter(seed);
  std::uniform_real_distribution<double> factor(0.5, 1.5);
  std::vector<Sample> samples;
  const auto end = start + std::chrono::duration_cast<Clock::duration>(limits.duration);
  while (true) {
    const int64_t i = next.fetch_add(1, std::memory_order_relaxed);
    if (i >= limits.requests) break;
    std::optional<Clock::time_point> due;
    if (level.rate) {
      due = start + std::chrono::duration_cast<Clock::duration>(
                        std::chrono::duration<double>(double(i) / *level.rate));
      if (*due >= end) break;
      std::this_thread::sleep_until(*due);
    } else if (Clock::now() >= end) {
      break;
    }
    std::vector<TimedCall> calls = request(client, i);
    for (size_t k = 0; k < calls.size(); ++k) {
      const TimedCall& call = calls[k];
      const Clock::time_point sent = k == 0 && due ? *due : call.sent;
      samples.push_back({call.op, secondsBetween(sent, call.done), secondsBetween(start, call.done),
                         call.outcome});
    }
    if (!level.rate && !calls.empty() && calls.back().outcome.retryAfterMs > 0) {
      const auto wait = std::chrono::duration<double, std::milli>(
          double(calls.back().outcome.retryAfterMs) * factor(jitter));
      std::this_thread::sleep_until(
          std::min(end, calls.back().done + std::chrono::duration_cast<Clock::duration>(wait)));
    }
  }
  return samples;
}

}  // namespace

PhaseResult runPhase(const std::vector<BenchClient*>& clients, const PhaseRequest& request,
                     const LoadLevel& level, const PhaseLimits& limits) {
  const int workers = std::min<int>(level.workers, static_cast<int>(clients.size()));
  std::vector<std::vector<Sample>> perWorker(static_cast<size_t>(workers));
  std::atomic<int64_t> next{0};
  const Clock::time_point start = Clock::now();
  {
    std::vector<std::jthread> threads;
    threads.reserve(perWorker.size());
    for (int w = 0; w < workers; ++w) {
      threads.emplace_back([&, w] {
        perWorker[w] = work(*clients[w], request, level, limits, start, next, unsigned(w) + 1);
      });
    }
  }  // joins
  PhaseResult result;
  for (auto& samples : perWorker) {
    for (Sample& s : samples) {
      result.seconds = std::max(result.seconds, s.endSeconds);
      result.samples.push_back(s);
    }
  }
  return result;
}

PhaseRequest mixRequests(const std::vector<BenchOp>& schedule) {
  return [&schedule](BenchClient& client, int64_t i) {
    const BenchOp op = schedule[static_cast<size_t>(i) % schedule.size()];
    const Clock::time_point sent = Clock::now();
    CallOutcome outcome = client.call(op, static_cast<uint64_t>(i));
    return std::vector<TimedCall>{{op, std::move(outcome), sent, Clock::now()}};
  };
}

std::vector<BenchOp> interleaveMix(const std::vector<std::pair<BenchOp, int>>& weights) {
  int total = 0;
  for (const auto& [op, weight] : weights) total += weight;
  std::vector<int> current(weights.size(), 0);
  std::vector<BenchOp> sequence;
  for (int step = 0; step < total; ++step) {
    size_t best = 0;
    for (size_t k = 0; k < weights.size(); ++k) {
      current[k] += weights[k].second;
      if (current[k] > current[best]) best = k;
    }
    current[best] -= total;
    sequence.push_back(weights[best].first);
  }
  return sequence;
}

}  // namespace tessera::cli
