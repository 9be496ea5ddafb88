#include "server/tessellation/test_engines.h"

#include <chrono>
#include <stdexcept>
#include <thread>

namespace tessera::server {
namespace {

class BlockingTestEngine final : public TessellationEngine {
 public:
  std::string name() const override { return "test-block"; }
  bool available() const override { return true; }
  std::string detail() const override { return "test engine: waits until cancelled"; }

  TessellationOutput run(const ControlMesh&, const TessellationJob& job,
                         const CancellationToken& cancel) override {
    if (job.reportProgress) job.reportProgress("test-blocking", 0.0);
    // Bounded, so that a test that forgets to cancel cannot hang the server forever.
    auto giveUp = std::chrono::steady_clock::now() + std::chrono::minutes(5);
    while (std::chrono::steady_clock::now() < giveUp) {
      cancel.throwIfCancelled();
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    throw TessellationUnavailable("test engine: gave up waiting for cancellation");
  }
};

class PatternTestEngine final : public TessellationEngine {
 public:
  std::string name() const override { return "test-pattern"; }
  bool available() const override { return true; }
  std::string detail() const override { return "test engine: returns a fixed byte pattern"; }

  TessellationOutput run(const ControlMesh&, const TessellationJob& job,
                         const CancellationToken& cancel) override {
    cancel.throwIfCancelled();
    if (job.reportProgress) job.reportProgress("test-pattern", 0.5);
    TessellationOutput output;
    output.glb.resize(kPatternBytes);
    for (size_t i = 0; i < output.glb.size(); ++i) output.glb[i] = patternByte(i);
    output.summary.timings.push_back({"test-pattern", 0.0});
    output.summary.tolerance = job.accuracy.tolerance;  // what an engine reports for a tolerance it kept
    return output;
  }
};

}  // namespace

std::unique_ptr<TessellationEngine> makeTestEngine(const std::string& kind) {
  if (kind == "block") return std::make_unique<BlockingTestEngine>();
  if (kind == "pattern") return std::make_unique<PatternTestEngine>();
  throw std::invalid_argument("--test-engine must be block or pattern");
}

}  // namespace tessera::server
