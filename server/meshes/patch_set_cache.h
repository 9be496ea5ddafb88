// Preprocessed patch sets (core's buildPatchSet) shared by every engine of a server, the
// tessellation engine and the renderer alike, within one byte budget: a mesh drawn and then
// tessellated is preprocessed once, and the budget the operator sets is the memory it takes.
#pragma once

#include <memory>
#include <string>

#include "core/mesh/control_mesh.h"
#include "core/rings/patch_set.h"
#include "server/calls/cancellation.h"
#include "server/calls/memory_reservation.h"
#include "server/meshes/lru_cache.h"

namespace tessera::server {

class PatchSetCache {
 public:
  // maxRefinedVertices: core's PreprocessingOptions limit, applied to every mesh preprocessed.
  PatchSetCache(size_t byteBudget, int64_t maxRefinedVertices)
      : cache_(byteBudget), maxRefinedVertices_(maxRefinedVertices) {}

  // The mesh's patch set, built on a miss. Keyed by id and content hash, so a mesh re-uploaded
  // under the same id never meets a stale entry. Throws what buildPatchSet throws, and
  // OperationCancelled when `cancel` fires while building (nothing is cached then). A build
  // reserves its memory in `memory` (may be null) as the refinement's size becomes known
  // (core/pipeline/memory_estimates.h), and keeps it until the job ends.
  std::shared_ptr<const PatchSet> get(const ControlMesh& mesh, const std::string& meshId,
                                      const std::string& meshSha256, const CancellationToken& cancel,
                                      MemoryReservation* memory);
  CacheStats stats() const { return cache_.stats(); }

 private:
  LruCache<std::string, PatchSet> cache_;
  int64_t maxRefinedVertices_;
};

}  // namespace tessera::server
