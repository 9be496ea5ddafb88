#include "bench/machine_load.h"

#include <pthread.h>
#include <sched.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

namespace tessera::bench {

CpuSample sampleCpu() {
  CpuSample sample;
  {
    std::ifstream stat("/proc/stat");
    std::string cpu;
    long long user = 0, nice = 0, system = 0, idle = 0, iowait = 0, irq = 0, softirq = 0, steal = 0;
    stat >> cpu >> user >> nice >> system >> idle >> iowait >> irq >> softirq >> steal;
    sample.machineBusy = user + nice + system + irq + softirq + steal;
    sample.machineTotal = sample.machineBusy + idle + iowait;
  }
  {
    // Fields 14 and 15 (utime, stime) follow the parenthesised command name, which may hold spaces.
    std::ifstream stat("/proc/self/stat");
    std::string line;
    std::getline(stat, line);
    std::istringstream rest(line.substr(line.rfind(')') + 2));
    std::string field;
    long long utime = 0, stime = 0;
    for (int i = 3; i <= 15 && rest >> field; ++i) {
      if (i == 14) utime = std::stoll(field);
      if (i == 15) stime = std::stoll(field);
    }
    sample.self = utime + stime;
  }
  return sample;
}

double othersShare(const CpuSample& before, const CpuSample& after) {
  long long total = after.machineTotal - before.machineTotal;
  if (total <= 0) return 0.0;
  long long others = (after.machineBusy - before.machineBusy) - (after.self - before.self);
  return others < 0 ? 0.0 : double(others) / double(total);
}

namespace {

bool pinToCore(int core) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(core, &set);
  return pthread_setaffinity_np(pthread_self(), sizeof set, &set) == 0;
}

}  // namespace

double coreRoundTripNs() {
  if (std::thread::hardware_concurrency() < 2) return 0;
  constexpr int kTrips = 20000;
  alignas(64) std::atomic<int> turn{0};
  std::thread partner([&turn] {
    pinToCore(1);
    for (int i = 0; i < kTrips; ++i) {
      while (turn.load(std::memory_order_acquire) != 2 * i + 1) {
      }
      turn.store(2 * i + 2, std::memory_order_release);
    }
  });
  cpu_set_t previous;
  pthread_getaffinity_np(pthread_self(), sizeof previous, &previous);
  pinToCore(0);
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kTrips; ++i) {
    turn.store(2 * i + 1, std::memory_order_release);
    while (turn.load(std::memory_order_acquire) != 2 * i + 2) {
    }
  }
  const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count();
  partner.join();
  pthread_setaffinity_np(pthread_self(), sizeof previous, &previous);
  return ns / kTrips;
}

}  // namespace tessera::bench
