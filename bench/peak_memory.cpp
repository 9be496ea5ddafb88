#include "bench/peak_memory.h"

#include <malloc.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <string>

namespace tessera::bench {
namespace {

// A "VmRSS:"-style field of /proc/self/status, in bytes (-1 where it is missing).
int64_t statusBytes(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(field, 0) == 0) return std::stoll(line.substr(std::strlen(field))) * 1024;
  }
  return -1;
}

double mib(int64_t bytes) {
  return double(bytes) / double(1 << 20);
}

// Restarts VmHWM at VmRSS; false when the kernel did not. Restarted, the mark is the resident
// size at the restart, which lies between the sizes read just before and just after it (but for
// a page or two touched meanwhile); not restarted, it stays at an earlier, higher peak.
bool restartHighWaterMark() {
  const int64_t before = statusBytes("VmRSS:");
  std::ofstream("/proc/self/clear_refs") << "5";
  const int64_t after = statusBytes("VmRSS:");
  return statusBytes("VmHWM:") <= std::max(before, after) + (int64_t(64) << 10);
}

}  // namespace

PeakMemory::PeakMemory() {
  malloc_trim(0);
  restartWorks_ = restartHighWaterMark();
  baseline_ = statusBytes("VmRSS:");
}

void PeakMemory::restart() {
  restartWorks_ = restartHighWaterMark() && restartWorks_;
}

void PeakMemory::record() {
  peak_ = std::max(peak_, statusBytes("VmHWM:") - baseline_);
}

double PeakMemory::peakMiB() const {
  return mib(peak_);
}

double PeakMemory::residentMiB() const {
  return mib(statusBytes("VmRSS:") - baseline_);
}

}  // namespace tessera::bench
