// CPU time of a running process as the kernel accounts it (/proc/PID/stat), for tests that check
// the server stops working when its calls end: user plus system time of all its threads.
#pragma once

#include <sys/types.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

namespace tessera::test {

// Seconds of CPU the process has used, or -1 if it is gone.
inline double processCpuSeconds(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
  const size_t close = text.rfind(')');  // the command name may hold spaces
  if (close == std::string::npos) return -1;
  std::istringstream fields(text.substr(close + 2));
  std::string field;
  long long utime = 0, stime = 0;
  // After the name: state is field 3; utime and stime are fields 14 and 15.
  for (int i = 3; i <= 15 && fields >> field; ++i) {
    if (i == 14) utime = std::stoll(field);
    if (i == 15) stime = std::stoll(field);
  }
  return double(utime + stime) / double(sysconf(_SC_CLK_TCK));
}

// Seconds until the process is idle (under 10 % of one core over a 300 ms window), measured from
// now; -1 if it is still busy after `limit` seconds.
inline double secondsUntilIdle(pid_t pid, double limit) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  constexpr auto kWindow = std::chrono::milliseconds(300);
  for (;;) {
    const auto from = Clock::now();
    const double before = processCpuSeconds(pid);
    std::this_thread::sleep_for(kWindow);
    const double used = processCpuSeconds(pid) - before;
    const double window = std::chrono::duration<double>(Clock::now() - from).count();
    if (used < 0.1 * window) return std::chrono::duration<double>(from - start).count();
    if (std::chrono::duration<double>(Clock::now() - start).count() > limit) return -1;
  }
}

}  // namespace tessera::test
