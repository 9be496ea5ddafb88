#include "client/remote_bench_cold.h"

#include <fmt/format.h>

namespace tessera::cli {
namespace {

// Copies of different seeds never share content: the seed picks a block of copy numbers.
uint64_t copyNumber(int seed, int64_t index) {
  return (uint64_t(seed) << 32) + uint64_t(index);
}

}  // namespace

std::string coldMeshId(int seed, int64_t index) {
  return fmt::format("bench-cold-{}-{}", seed, index);
}

PhaseRequest coldRequests(const std::vector<ColdSource>& sources,
                          const std::vector<tessera::v1::TessellateRequest>& requests, int seed,
                          int64_t firstIndex) {
  return [&sources, &requests, seed, firstIndex](BenchClient& client, int64_t i) {
    const int64_t index = firstIndex + i;
    const size_t k = static_cast<size_t>(index) % sources.size();
    const ColdSource& source = sources[k];
    UploadOptions options;
    options.meshId = coldMeshId(seed, index);
    options.displayName = fmt::format("cold copy {} of {}", index, source.name);
    options.subdivision = source.options;
    const tessera::v1::MeshArrays copy = coldCopy(source, copyNumber(seed, index));
    std::vector<TimedCall> calls;
    auto timed = [&calls](BenchOp op, auto call) {
      const BenchClock::time_point sent = BenchClock::now();
      CallOutcome outcome = call();
      calls.push_back({op, std::move(outcome), sent, BenchClock::now()});
      return calls.back().outcome.ok();
    };
    if (!timed(BenchOp::kUpload, [&] { return client.upload(copy, options); })) return calls;
    tessera::v1::TessellateRequest request = requests[k];
    request.set_name("meshes/" + options.meshId);
    timed(BenchOp::kTessellate, [&] { return client.tessellate(request); });
    return calls;
  };
}

}  // namespace tessera::cli
