// Memory a heavy job freed, given back to the operating system when its call ends. glibc keeps
// freed heap memory for reuse (and raises its mmap threshold after large frees, so later large
// buffers come from the heap too): without this a server kept ~160 MB past its caches after one
// tessellation of armorguy at 1e-4 (tests/server/memory_release_test.cpp).
#pragma once

#include <malloc.h>

namespace tessera::server {

// Blocks of kMappedBlock bytes and more are mapped on their own, whatever was freed before.
// glibc's threshold otherwise moves up to the largest block freed (up to 32 MiB), and a large
// job's buffers then land in the heap beside what the caches keep from the same job, whose pages
// malloc_trim cannot give back: after one tessellation of armorguy at 1e-4 the server kept 13-87
// MiB past its caches from run to run (MemoryRelease failed at 64), with the threshold fixed at
// 1, 4 or 16 MiB -4 to -2 MiB in every run, its peak 880 -> 811 MiB at 4 MiB (2026-12-08). Buffers
// under 4 MiB (a warm GLB of bigguy at 1e-3) are reused from the heap as before. Call once, before
// the server starts threads.
inline void mapLargeBlocks() {
  constexpr int kMappedBlock = 4 << 20;
  mallopt(M_MMAP_THRESHOLD, kMappedBlock);
}

class ReleaseMemoryOnExit {
 public:
  ReleaseMemoryOnExit() = default;
  ReleaseMemoryOnExit(const ReleaseMemoryOnExit&) = delete;
  ReleaseMemoryOnExit& operator=(const ReleaseMemoryOnExit&) = delete;
  ~ReleaseMemoryOnExit() { malloc_trim(0); }
};

}  // namespace tessera::server
