#include "server/calls/machine_memory.h"

#include <algorithm>
#include <fstream>
#include <string>

namespace tessera::server {
namespace {

// A cgroup limit file's value in bytes; 0 for "max", an absurd v1 "unlimited" or no file.
int64_t cgroupLimit(const char* path) {
  std::ifstream in(path);
  std::string text;
  if (!(in >> text) || text == "max") return 0;
  try {
    const long double value = std::stold(text);
    return value > 0 && value < 1e18L ? int64_t(value) : 0;
  } catch (const std::exception&) {
    return 0;
  }
}

int64_t memTotal() {
  std::ifstream in("/proc/meminfo");
  std::string key, unit;
  int64_t kib = 0;
  while (in >> key >> kib >> unit) {
    if (key == "MemTotal:") return kib * 1024;
  }
  return 0;
}

}  // namespace

int64_t machineMemoryBytes() {
  int64_t bytes = memTotal();
  for (const char* path : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    const int64_t limit = cgroupLimit(path);
    if (limit > 0) bytes = bytes > 0 ? std::min(bytes, limit) : limit;
  }
  return bytes;
}

}  // namespace tessera::server
