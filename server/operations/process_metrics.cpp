#include "server/operations/process_metrics.h"

#include <grpcpp/grpcpp.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "core/base/version.h"

namespace tessera::server {
namespace {

// The fields of /proc/self/stat after the command name (which may hold spaces and parentheses,
// so the split starts after its closing parenthesis): index 0 is field 3, the state.
std::vector<std::string> statFields() {
  std::ifstream in("/proc/self/stat");
  std::string line;
  std::getline(in, line);
  const size_t close = line.rfind(')');
  if (close == std::string::npos) return {};
  std::istringstream rest(line.substr(close + 1));
  std::vector<std::string> fields;
  for (std::string field; rest >> field;) fields.push_back(field);
  return fields;
}

// Field n of proc(5)'s numbering (1-based: utime is 14, starttime 22, vsize 23, rss 24).
double statField(const std::vector<std::string>& fields, int n) {
  const size_t index = size_t(n - 3);
  return index < fields.size() ? std::stod(fields[index]) : std::nan("");
}
double statField(int n) {
  return statField(statFields(), n);
}

double bootTimeSeconds() {
  std::ifstream in("/proc/stat");
  for (std::string key; in >> key;) {
    if (key == "btime") {
      double seconds = 0;
      in >> seconds;
      return seconds;
    }
    in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  return std::nan("");
}

double ticksPerSecond() {
  return double(sysconf(_SC_CLK_TCK));
}

// utime + stime, from one read of the file.
double cpuSeconds() {
  const std::vector<std::string> fields = statFields();
  return (statField(fields, 14) + statField(fields, 15)) / ticksPerSecond();
}

double openFileDescriptors() {
  double count = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator("/proc/self/fd"))
    ++count;
  return count - 1;  // the directory iterator's own descriptor
}

double maxFileDescriptors() {
  rlimit limit{};
  if (getrlimit(RLIMIT_NOFILE, &limit) != 0) return std::nan("");
  return limit.rlim_cur == RLIM_INFINITY ? std::nan("") : double(limit.rlim_cur);
}

}  // namespace

void registerProcessMetrics(MetricsRegistry& registry) {
  registry.info("tessera_build_info",
                "The server's version, the gRPC it was built with and its compiler.",
                {"version", "grpc", "compiler"}, {kVersion, grpc::Version(), __VERSION__});
  registry.sampled("process_cpu_seconds_total", "User and system CPU time spent, in seconds.",
                   "counter", cpuSeconds);
  registry.sampled("process_resident_memory_bytes", "Resident memory size in bytes.", "gauge",
                   [] { return statField(24) * double(sysconf(_SC_PAGESIZE)); });
  registry.sampled("process_virtual_memory_bytes", "Virtual memory size in bytes.", "gauge",
                   [] { return statField(23); });
  const double start = bootTimeSeconds() + statField(22) / ticksPerSecond();
  registry.sampled("process_start_time_seconds",
                   "Start time of the process since the Unix epoch, in seconds.", "gauge",
                   [start] { return start; });
  registry.sampled("process_open_fds", "Open file descriptors.", "gauge", openFileDescriptors);
  registry.sampled("process_max_fds", "The limit on open file descriptors.", "gauge",
                   maxFileDescriptors);
}

}  // namespace tessera::server
