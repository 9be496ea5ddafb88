#include "server/meshes/patch_set_cache.h"

#include "core/pipeline/memory_estimates.h"
#include "core/pipeline/preprocessing.h"
#include "core/surface/adaptive_surface.h"

#include <stdexcept>
#include <vector>

namespace tessera::server {
namespace {

template <typename T>
size_t bytesOf(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

// What a patch set holds, as charged against the budget.
size_t bytesOf(const PatchSet& set) {
  const RegularPatches& g = set.regular;
  const RingSet& r = set.rings;
  return sizeof(PatchSet) + bytesOf(g.bspline) + bytesOf(g.domains) + bytesOf(g.levels) +
         bytesOf(r.shapes) + bytesOf(r.cornerEv) + bytesOf(r.levels) + bytesOf(r.pointOffsets) +
         bytesOf(r.points) + bytesOf(r.centers) + bytesOf(r.spokeOffsets) + bytesOf(r.sharpSpokes) +
         bytesOf(r.sectorOffsets) + bytesOf(r.sectorDomains) + bytesOf(r.sectorOwned) +
         (set.adaptive ? set.adaptive->bytes() : 0);
}

}  // namespace

std::shared_ptr<const PatchSet> PatchSetCache::get(const ControlMesh& mesh,
                                                   const std::string& meshSha256,
                                                   const CancellationToken& cancel,
                                                   MemoryReservation* memory) {
  // Without it every mesh would share one entry.
  if (meshSha256.empty()) {
    throw std::invalid_argument("PatchSetCache::get: the mesh's SHA-256 is missing");
  }
  bool built = false;
  auto build = [&] {
    built = true;
    misses_.fetch_add(1);
    PreprocessingOptions options{[&cancel] { cancel.throwIfCancelled(); }, maxRefinedVertices_};
    int64_t held = 0;
    if (memory) {
      options.beforeRefining = [&](int64_t estimate) {
        memory->hold(held, refinementBytes(estimate), "OpenSubdiv's refinement of the mesh");
      };
      options.afterRefining = [&](int64_t refined) {
        memory->hold(held, preprocessingBytes(mesh, refined), "preprocessing the mesh");
      };
    }
    auto patches = std::make_shared<const PatchSet>(buildPatchSet(mesh, options));
    cache_.insert(meshSha256, patches, bytesOf(*patches));
    return patches;
  };
  std::shared_ptr<const PatchSet> patches =
      builds_.get(meshSha256, cancel, memory, [&] { return cache_.find(meshSha256); }, build);
  if (!built) hits_.fetch_add(1);
  return patches;
}

CacheStats PatchSetCache::stats() const {
  CacheStats stats = cache_.stats();  // its own hits and misses count every look, retries too
  stats.hits = hits_.load();
  stats.misses = misses_.load();
  return stats;
}

}  // namespace tessera::server
