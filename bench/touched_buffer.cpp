#include "bench/touched_buffer.h"

#include <sys/mman.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <new>

namespace tessera::bench {

namespace {
constexpr size_t kHugePage = size_t(2) << 20;
}  // namespace

void* allocateTouched(size_t bytes) {
  // Huge-page alignment lets madvise back the range with 2 MiB pages: fewer TLB misses for
  // every method alike, so the comparison measures the methods, not page walks.
  const size_t rounded = std::max(kHugePage, (bytes + kHugePage - 1) / kHugePage * kHugePage);
  void* data = std::aligned_alloc(kHugePage, rounded);
  if (data == nullptr) throw std::bad_alloc();
  madvise(data, rounded, MADV_HUGEPAGE);  // advisory: a refusal only costs speed
  std::memset(data, 0, rounded);
  return data;
}

void freeTouched(void* data) { std::free(data); }

}  // namespace tessera::bench
