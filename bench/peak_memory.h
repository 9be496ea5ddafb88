// The process's peak resident memory over a piece of work, measured as tools/memory_fit does for
// bench/MEMORY-RESULTS.md: free heap given back (malloc_trim), the kernel's high-water mark
// (VmHWM) restarted at the resident size by writing "5" to /proc/self/clear_refs, and read
// again after. It counts every page the process touches meanwhile, on every thread (TBB's
// workers included), so it is the memory a server would have to admit the job with.
#pragma once

#include <cstdint>

namespace tessera::bench {

class PeakMemory {
 public:
  // Trims the heap and takes the resident size now as the baseline peaks are measured from.
  PeakMemory();

  // Restarts the kernel's high-water mark at the resident size now, without trimming (cheap
  // enough to do between timed iterations, outside them).
  void restart();
  // Takes the high-water mark since the last restart into the peak.
  void record();

  // The largest recorded high-water mark above the baseline, in MiB.
  double peakMiB() const;
  // Resident size now above the baseline, in MiB: what work done since then keeps.
  double residentMiB() const;
  // Whether /proc/self/clear_refs restarted the mark (false on kernels or sandboxes that refuse
  // it: the peak is then the process's own since its start, an upper bound).
  bool restartWorks() const { return restartWorks_; }

 private:
  int64_t baseline_ = 0, peak_ = 0;
  bool restartWorks_ = true;
};

}  // namespace tessera::bench
