#include "server/meshes/patch_set_cache.h"

#include "core/pipeline/memory_estimates.h"
#include "core/pipeline/preprocessing.h"
#include "core/surface/adaptive_surface.h"
#include "core/surface/surface_tree.h"

#include <stdexcept>
#include <cmath>
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

// Content and chain floor (a power of ten: its exponent names it).
std::string keyAt(const std::string& meshSha256, double chainFloor) {
  return meshSha256 + "@1e" + std::to_string(int(std::lround(std::log10(chainFloor))));
}

}  // namespace

std::shared_ptr<const PatchSet> PatchSetCache::get(const ControlMesh& mesh,
                                                   const std::string& meshSha256,
                                                   const CancellationToken& cancel,
                                                   MemoryReservation* memory,
                                                   double finestRelativeTolerance) {
  // Without it every mesh would share one entry.
  if (meshSha256.empty()) {
    throw std::invalid_argument("PatchSetCache::get: the mesh's SHA-256 is missing");
  }
  const double floor = chainFloorFor(finestRelativeTolerance);
  bool built = false;
  auto build = [&] {
    built = true;
    misses_.fetch_add(1);
    PreprocessingOptions options{[&cancel] { cancel.throwIfCancelled(); }, maxRefinedVertices_};
    options.finestRelativeTolerance = finestRelativeTolerance;
    int64_t held = 0;
    if (memory) {
      options.beforeRefining = [&](int64_t estimate) {
        memory->hold(held, refinementBytes(estimate), "OpenSubdiv's refinement of the mesh");
      };
      options.afterRefining = [&](int64_t refined) {
        memory->hold(held, preprocessingBytes(mesh, refined), "preprocessing the mesh");
      };
    }
    validateControlMesh(mesh);
    std::shared_ptr<const PatchSet> patches;
    const std::string topologyKey = "topology:" + topologySha256(mesh);
    if (seenBefore(topologyKey)) {
      std::shared_ptr<const MeshTopology> topology = topologyOf(mesh, topologyKey, cancel, memory, options);
      patches = std::make_shared<const PatchSet>(buildPatchSet(mesh, *topology, options));
    } else {
      topologyMisses_.fetch_add(1);  // built, and freed once the pieces are gathered
      patches = std::make_shared<const PatchSet>(buildPatchSet(mesh, options));
    }
    cache_.insert(keyAt(meshSha256, floor), std::make_shared<const Entry>(Entry{patches, nullptr}), bytesOf(*patches));
    return patches;
  };
  auto cached = [&] { return cachedFor(meshSha256, floor); };
  std::shared_ptr<const PatchSet> patches = builds_.get(keyAt(meshSha256, floor), cancel, memory, cached, build);
  if (!built) hits_.fetch_add(1);
  return patches;
}

// Built with the first mesh's options (its refinement hooks reserve the job's memory); a build
// another call has under way is waited for.
bool PatchSetCache::seenBefore(const std::string& topologyKey) {
  if (seen_.find(topologyKey)) return true;
  seen_.insert(topologyKey, std::make_shared<const char>(1), topologyKey.size() + kSeenEntryBytes);
  return false;
}

std::shared_ptr<const MeshTopology> PatchSetCache::topologyOf(const ControlMesh& mesh, const std::string& key,
                                                              const CancellationToken& cancel,
                                                              MemoryReservation* memory,
                                                              const PreprocessingOptions& options,
                                                              bool* builtHere) {
  bool built = false;
  auto build = [&] {
    built = true;
    topologyMisses_.fetch_add(1);
    auto topology = buildMeshTopology(mesh, options);
    cache_.insert(key, std::make_shared<const Entry>(Entry{nullptr, topology}), topology->bytes());
    return topology;
  };
  auto cached = [&]() -> std::shared_ptr<const MeshTopology> {
    const std::shared_ptr<const Entry> found = cache_.find(key);
    return found ? found->topology : nullptr;
  };
  std::shared_ptr<const MeshTopology> topology = topologyBuilds_.get(key, cancel, memory, cached, build);
  if (builtHere) {
    *builtHere = built;
  } else if (!built) {
    topologyHits_.fetch_add(1);
  }
  return topology;
}

bool PatchSetCache::keepTopology(const ControlMesh& mesh, const CancellationToken& cancel,
                                 MemoryReservation* memory) {
  const std::string key = "topology:" + topologySha256(mesh);
  seenBefore(key);  // from now on every patch set of this topology keeps and uses it
  if (cache_.find(key)) return false;
  PreprocessingOptions options{[&cancel] { cancel.throwIfCancelled(); }, maxRefinedVertices_};
  int64_t held = 0;
  if (memory) {
    options.beforeRefining = [&](int64_t estimate) {
      memory->hold(held, refinementBytes(estimate), "OpenSubdiv's refinement of the mesh");
    };
  }
  bool built = false;
  // Waiting for another call's build is no preprocessing that reused a topology: not a hit.
  topologyOf(mesh, key, cancel, memory, options, &built);
  return built;
}

bool PatchSetCache::holdsTopology(const ControlMesh& mesh) {
  return cache_.find("topology:" + topologySha256(mesh)) != nullptr;
}

CacheStats PatchSetCache::topologyStats() const {
  CacheStats stats;
  stats.hits = topologyHits_.load();
  stats.misses = topologyMisses_.load();
  return stats;
}

std::shared_ptr<const PatchSet> PatchSetCache::cachedFor(const std::string& meshSha256, double floor) {
  // Any chain floor at or below this request's serves it, the finest (kChainFloor) last.
  for (double at = floor; at >= kChainFloor * (1 - 1e-9); at /= 10) {
    if (auto found = cache_.find(keyAt(meshSha256, at))) return found->patches;
  }
  return nullptr;
}

bool PatchSetCache::holds(const std::string& meshSha256, double finestRelativeTolerance) {
  return cachedFor(meshSha256, chainFloorFor(finestRelativeTolerance)) != nullptr;
}

CacheStats PatchSetCache::stats() const {
  CacheStats stats = cache_.stats();  // its own hits and misses count every look, retries too
  stats.hits = hits_.load();
  stats.misses = misses_.load();
  return stats;
}

}  // namespace tessera::server
