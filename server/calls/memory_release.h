// Memory a heavy job freed, given back to the operating system when its call ends. glibc keeps
// freed heap memory for reuse (and raises its mmap threshold after large frees, so later large
// buffers come from the heap too): without this a server kept ~160 MB past its caches after one
// tessellation of armorguy at 1e-4 (tests/server/memory_release_test.cpp).
#pragma once

#include <malloc.h>

namespace tessera::server {

class ReleaseMemoryOnExit {
 public:
  ReleaseMemoryOnExit() = default;
  ReleaseMemoryOnExit(const ReleaseMemoryOnExit&) = delete;
  ReleaseMemoryOnExit& operator=(const ReleaseMemoryOnExit&) = delete;
  ~ReleaseMemoryOnExit() { malloc_trim(0); }
};

}  // namespace tessera::server
