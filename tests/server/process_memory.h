// Memory of a running process as the kernel accounts it (/proc/PID/status), for tests that check
// the server's memory stays bounded: VmRSS (resident now) and VmHWM (the peak of VmRSS so far).
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <fstream>
#include <string>

namespace tessera::test {

// The field ("VmRSS", "VmHWM") in bytes, or -1 if the process or the field is missing.
inline int64_t processMemoryBytes(pid_t pid, const std::string& field) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind(field + ":", 0) == 0) return std::stoll(line.substr(field.size() + 1)) * 1024;
  }
  return -1;
}

}  // namespace tessera::test
