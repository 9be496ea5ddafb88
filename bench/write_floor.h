// The machine's memory write bandwidth, measured in the benchmark's own process: the floor under
// any method that must write a case's refined points to memory (paper Table 1 writes every level).
#pragma once

#include <cstddef>
#include <string>

namespace tessera::bench {

inline constexpr size_t kFloorBufferBytes = size_t(1) << 30;  // 1 GiB: far past every cache

enum class WriteMethod {
  kStreamAvx2,    // 32-byte non-temporal stores (what core/rings/fas.cpp's streamOut issues)
  kStreamAvx512,  // 64-byte non-temporal stores
  kMemset,        // glibc memset (its own choice of stores)
};

std::string writeMethodName(WriteMethod method);
bool writeMethodAvailable(WriteMethod method);

// Fills `floats` floats with `value`, split into `threads` contiguous parts written concurrently;
// returns the seconds from the first thread's start to the last thread's end.
double timedWrite(WriteMethod method, float* buffer, size_t floats, int threads, float value);

// Best bandwidth (bytes/s) seen by any write-floor measurement of this process. If none ran
// (e.g. --benchmark_filter=BM_Fas), measures the two-thread floor once: best of 10 passes of
// each write method over kFloorBufferBytes.
void recordWriteBandwidth(double bytesPerSecond);
double bestWriteBandwidth();

// The least time, over a few passes of every write method with all threads, to write `floats`
// floats into `buffer` (a case's own output buffer: same pages, same size, measured right beside
// the case's iterations, so host-level bandwidth swings hit both alike). Overwrites the buffer;
// also feeds recordWriteBandwidth.
double bufferWriteFloorSeconds(float* buffer, size_t floats, int threads);

// Never 0: on this host a pass writing zero bytes runs about twice as fast as one writing any
// other data (zero-line elimination below the guest), which would understate the floor.
float nonZeroFill(int pass);

}  // namespace tessera::bench
