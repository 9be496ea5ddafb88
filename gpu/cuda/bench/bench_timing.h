// What the CUDA benchmark programs share: comma-separated options and host timing.
#pragma once

#include <algorithm>
#include <chrono>
#include <sstream>
#include <string>
#include <vector>

namespace tessera::cuda::bench {

using Clock = std::chrono::steady_clock;

inline std::vector<std::string> split(const char* text) {
  std::vector<std::string> items;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) items.push_back(item);
  return items;
}

inline double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Median of `runs` timed calls of `work` after one untimed call.
template <class Work>
double medianMs(int runs, Work&& work) {
  work();
  std::vector<double> times;
  for (int r = 0; r < runs; ++r) {
    const Clock::time_point start = Clock::now();
    work();
    times.push_back(msSince(start));
  }
  std::nth_element(times.begin(), times.begin() + runs / 2, times.end());
  return times[size_t(runs / 2)];
}

}  // namespace tessera::cuda::bench
