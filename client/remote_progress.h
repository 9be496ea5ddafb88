// A one-line progress bar on stderr for uploads and tessellations, drawn only when stderr is a
// terminal so that logs and pipes stay clean.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>

namespace tessera::cli {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  ~ProgressBar();

  // fraction in [0, 1]; detail is shown after the bar (a stage name, bytes sent).
  void update(double fraction, std::string_view detail = {});
  // Ends the line (if one was drawn).
  void finish();

 private:
  std::string label_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point lastDraw_;
};

// "1.4 MiB" and the like.
std::string humanBytes(int64_t bytes);

}  // namespace tessera::cli
