#include "bench/machine_load.h"

#include <fstream>
#include <sstream>
#include <string>

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

}  // namespace tessera::bench
