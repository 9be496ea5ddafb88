#include "client/remote_bench_runner.h"

#include <algorithm>
#include <atomic>
#include <random>
#include <thread>

namespace tessera::cli {
namespace {

using Clock = std::chrono::steady_clock;

double secondsBetween(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

// One worker's loop: claims request numbers from next until the phase's count or time runs out.
// Closed-loop workers honour a busy server's retry hint, waiting 0.5–1.5 times it (jittered, so
// that refused workers do not come back together) before their next request; at a fixed rate
// the schedule is the load offered, and it is kept.
std::vector<Sample> work(BenchClient& client, const std::vector<BenchOp>& schedule,
                         const LoadLevel& level, const PhaseLimits& limits, Clock::time_point start,
                         std::atomic<int64_t>& next, unsigned seed) {
  std::minstd_rand jitter(seed);
  std::uniform_real_distribution<double> factor(0.5, 1.5);
  std::vector<Sample> samples;
  const auto end = start + std::chrono::duration_cast<Clock::duration>(limits.duration);
  while (true) {
    const int64_t i = next.fetch_add(1, std::memory_order_relaxed);
    if (i >= limits.requests) break;
    Clock::time_point sent = Clock::now();
    if (level.rate) {
      const auto due = start + std::chrono::duration_cast<Clock::duration>(
                                   std::chrono::duration<double>(double(i) / *level.rate));
      if (due >= end) break;
      std::this_thread::sleep_until(due);
      sent = due;
    } else if (sent >= end) {
      break;
    }
    const BenchOp op = schedule[static_cast<size_t>(i) % schedule.size()];
    CallOutcome outcome = client.call(op, static_cast<uint64_t>(i));
    const Clock::time_point done = Clock::now();
    samples.push_back({op, secondsBetween(sent, done), secondsBetween(start, done), outcome});
    if (!level.rate && outcome.retryAfterMs > 0) {
      const auto wait = std::chrono::duration<double, std::milli>(double(outcome.retryAfterMs) * factor(jitter));
      std::this_thread::sleep_until(std::min(end, done + std::chrono::duration_cast<Clock::duration>(wait)));
    }
  }
  return samples;
}

}  // namespace

PhaseResult runPhase(const std::vector<BenchClient*>& clients, const std::vector<BenchOp>& schedule,
                     const LoadLevel& level, const PhaseLimits& limits) {
  const int workers = std::min<int>(level.workers, static_cast<int>(clients.size()));
  std::vector<std::vector<Sample>> perWorker(static_cast<size_t>(workers));
  std::atomic<int64_t> next{0};
  const Clock::time_point start = Clock::now();
  {
    std::vector<std::jthread> threads;
    threads.reserve(perWorker.size());
    for (int w = 0; w < workers; ++w) {
      threads.emplace_back(
          [&, w] { perWorker[w] = work(*clients[w], schedule, level, limits, start, next, unsigned(w) + 1); });
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
