#include "bench/write_floor.h"

#include <immintrin.h>

#include <algorithm>
#include <atomic>
#include <barrier>
#include <chrono>
#include <cstring>
#include <mutex>
#include <thread>
#include <vector>

#include "bench/ring_workload.h"
#include "bench/touched_buffer.h"

namespace tessera::bench {

namespace {

using Clock = std::chrono::steady_clock;

__attribute__((target("avx2"))) void streamAvx2(float* out, size_t floats, float value) {
  const __m256 v = _mm256_set1_ps(value);
  size_t i = 0;
  for (; i + 8 <= floats; i += 8) _mm256_stream_ps(out + i, v);
  for (; i < floats; ++i) out[i] = value;
  _mm_sfence();
}

__attribute__((target("avx512f"))) void streamAvx512(float* out, size_t floats, float value) {
  const __m512 v = _mm512_set1_ps(value);
  size_t i = 0;
  for (; i + 16 <= floats; i += 16) _mm512_stream_ps(out + i, v);
  for (; i < floats; ++i) out[i] = value;
  _mm_sfence();
}

void writePart(WriteMethod method, float* out, size_t floats, float value) {
  switch (method) {
    case WriteMethod::kStreamAvx2:
      return streamAvx2(out, floats, value);
    case WriteMethod::kStreamAvx512:
      return streamAvx512(out, floats, value);
    case WriteMethod::kMemset: {
      unsigned char byte = static_cast<unsigned char>(1 + int(value) % 255);  // never zero
      std::memset(out, byte, floats * sizeof(float));
      return;
    }
  }
}

std::mutex floorMutex;
double bestBandwidth = 0.0;

}  // namespace

std::string writeMethodName(WriteMethod method) {
  switch (method) {
    case WriteMethod::kStreamAvx2:
      return "stream_avx2";
    case WriteMethod::kStreamAvx512:
      return "stream_avx512";
    case WriteMethod::kMemset:
      return "memset";
  }
  return "unknown";
}

bool writeMethodAvailable(WriteMethod method) {
  if (method == WriteMethod::kStreamAvx512) return __builtin_cpu_supports("avx512f");
  if (method == WriteMethod::kStreamAvx2) return __builtin_cpu_supports("avx2");
  return true;
}

double timedWrite(WriteMethod method, float* buffer, size_t floats, int threads, float value) {
  // Parts are whole 4 KiB pages so that no two threads share a cache line.
  const size_t pageFloats = 4096 / sizeof(float);
  const size_t partFloats = (floats / threads + pageFloats - 1) / pageFloats * pageFloats;
  std::vector<Clock::time_point> starts(threads), ends(threads);
  std::barrier ready(threads);
  auto work = [&](int t) {
    size_t begin = std::min(floats, size_t(t) * partFloats);
    size_t end = std::min(floats, begin + partFloats);
    ready.arrive_and_wait();  // thread start-up stays outside the measured span
    starts[t] = Clock::now();
    writePart(method, buffer + begin, end - begin, value);
    ends[t] = Clock::now();
  };
  std::vector<std::thread> helpers;
  for (int t = 1; t < threads; ++t) helpers.emplace_back(work, t);
  work(0);
  for (auto& helper : helpers) helper.join();
  auto first = *std::min_element(starts.begin(), starts.end());
  auto last = *std::max_element(ends.begin(), ends.end());
  return std::chrono::duration<double>(last - first).count();
}

void recordWriteBandwidth(double bytesPerSecond) {
  std::lock_guard lock(floorMutex);
  bestBandwidth = std::max(bestBandwidth, bytesPerSecond);
}

double bestWriteBandwidth() {
  {
    std::lock_guard lock(floorMutex);
    if (bestBandwidth > 0) return bestBandwidth;
  }
  // The host's memory bandwidth varies from pass to pass (other tenants), so take the best of
  // many passes: the floor is the least time the writes could take.
  TouchedBuffer<float> buffer(kFloorBufferBytes / sizeof(float));
  for (WriteMethod method :
       {WriteMethod::kStreamAvx2, WriteMethod::kStreamAvx512, WriteMethod::kMemset}) {
    if (!writeMethodAvailable(method)) continue;
    for (int pass = 0; pass < 10; ++pass) {
      double seconds = timedWrite(method, buffer.data(), buffer.size(), 2, nonZeroFill(pass));
      recordWriteBandwidth(double(buffer.bytes()) / seconds);
    }
  }
  std::lock_guard lock(floorMutex);
  return bestBandwidth;
}

float nonZeroFill(int pass) {
  return 1.0f + float(pass % 1000);
}

double bufferWriteFloorSeconds(float* buffer, size_t floats, int threads) {
  double best = 1e30;
  for (int pass = 0; pass < 3; ++pass) {
    for (WriteMethod method :
         {WriteMethod::kStreamAvx2, WriteMethod::kStreamAvx512, WriteMethod::kMemset}) {
      if (!writeMethodAvailable(method)) continue;
      best = std::min(best, timedWrite(method, buffer, floats, threads, nonZeroFill(pass)));
    }
  }
  recordWriteBandwidth(double(floats * sizeof(float)) / best);
  return best;
}

}  // namespace tessera::bench
