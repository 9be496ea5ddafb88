// Preprocessed patch sets (core's buildPatchSet) shared by every engine of a server, the
// tessellation engine and the renderer alike, within one byte budget: a mesh drawn and then
// tessellated is preprocessed once, and the budget the operator sets is the memory it takes.
//
// Keyed by content alone: the SHA-256 of the mesh's canonical encoding (core/mesh/mesh_codec.h),
// which holds every field of the ControlMesh that preprocessing reads (positions, faces, creases,
// corners, holes, the subdivision rules with the UV interpolation, UVs and their indices, the
// origin). The only other input, the refinement limit, is the cache's own. So identical content
// under another id, or uploaded again, meets the patch set already built, and a mesh deleted and
// re-uploaded with other content under the same id never meets a stale one. Concurrent misses of
// one key build it once (single_flight.h).
//
// A patch set's topology (core's MeshTopology: Far's refinement, the pieces' layout, the seams) is
// cached beside it, keyed by core's topologySha256: a mesh with the same faces, tags, rules and UV
// topology and moved vertices (a modelling tool's edited cage, a frame of an animated one) is
// preprocessed from its positions alone (docs/DECISIONS.md "Edits reuse topology"). A topology
// is kept from the second patch set built with it (an edit, or a finer request): a one-off
// request keeps no refinement, which is most of a topology's memory and, kept among the
// request's freed memory, holds pages the system does not get back. Both share the one byte
// budget, least recently used out first: a modelling tool's edit loop keeps its topology, which
// every edit uses, and its latest patch set, while the patch sets of earlier edits fall out.
#pragma once

#include <atomic>
#include <memory>
#include <string>

#include "core/base/error.h"
#include "core/mesh/control_mesh.h"
#include "core/pipeline/preprocessing.h"
#include "core/rings/patch_set.h"
#include "server/calls/cancellation.h"
#include "server/calls/memory_reservation.h"
#include "server/meshes/lru_cache.h"
#include "server/meshes/single_flight.h"

namespace tessera::server {

class PatchSetCache {
 public:
  // maxRefinedVertices: core's PreprocessingOptions limit, applied to every mesh preprocessed.
  PatchSetCache(size_t byteBudget, int64_t maxRefinedVertices)
      : cache_(byteBudget), maxRefinedVertices_(maxRefinedVertices) {}

  // The patch set of `mesh`, whose canonical encoding has SHA-256 `meshSha256` (hex, as
  // MeshMetadata and tessera.v1.Mesh give it): from the cache, from the build another call has
  // under way (waited for), or built here. A build reserves its memory in `memory` (may be null)
  // as the refinement's size becomes known (core/pipeline/memory_estimates.h) and keeps it until
  // the job ends; a call waiting for another's build reserves nothing for it. Throws what
  // buildPatchSet throws (TesseraError: the mesh's own failure, which calls waiting for the same
  // build get too), OperationCancelled when `cancel` fires while building or waiting (nothing is
  // cached then, and calls waiting for this build build it themselves), what `memory` throws, and
  // std::invalid_argument for an empty `meshSha256`.
  // `finestRelativeTolerance` (core's PreprocessingOptions; 0: any request) sets how deep the
  // surface's EV chains go: a patch set built for a finer one serves a coarser request, so a
  // coarse request is served by what is cached for this content at its chain floor or any finer
  // one, and builds at its own (the cold path, docs/ADAPTIVE.md §1a).
  std::shared_ptr<const PatchSet> get(const ControlMesh& mesh, const std::string& meshSha256,
                                      const CancellationToken& cancel, MemoryReservation* memory,
                                      double finestRelativeTolerance = 0);

  // Whether get() would find this content's patch set cached, for a request down to
  // `finestRelativeTolerance` (no preprocessing): how the server tells a cheap job before it is
  // admitted (server/tessellation/job_cost.h). Counts as a use of the entry, not as a hit.
  bool holds(const std::string& meshSha256, double finestRelativeTolerance);

  // For a positions-only upload (mesh_service.cpp), which says that meshes of this topology are
  // being edited: keeps `mesh`'s topology, so that the first patch set of every mesh sharing it
  // is built from it (a topology hit), the edited mesh's first included. Builds it (a topology
  // miss), reserving its refinement in `memory` (may be null), unless it is cached or being built;
  // returns whether this call built it. Throws what buildMeshTopology throws, OperationCancelled
  // and what `memory` throws.
  bool keepTopology(const ControlMesh& mesh, const CancellationToken& cancel, MemoryReservation* memory);
  // Whether `mesh`'s topology is cached (keepTopology would build nothing).
  bool holdsTopology(const ControlMesh& mesh);

  // hits: calls that found the patch set built (in the cache, or by the build they waited for);
  // misses: builds started (each preprocessing, finished or not); bytes and entries: patch sets
  // and topologies together.
  CacheStats stats() const;
  // hits: preprocessings that reused a cached topology; misses: topologies built, kept or not,
  // keepTopology's included (only these two).
  CacheStats topologyStats() const;

 private:
  // Whether a patch set of this topology was built before (and marks it so).
  bool seenBefore(const std::string& topologyKey);
  std::shared_ptr<const MeshTopology> topologyOf(const ControlMesh& mesh, const std::string& key,
                                                 const CancellationToken& cancel, MemoryReservation* memory,
                                                 const PreprocessingOptions& options,
                                                 bool* builtHere = nullptr);  // set: counts no hit
  std::shared_ptr<const PatchSet> cachedFor(const std::string& meshSha256, double chainFloor);

  // A cache entry: a patch set (keyed by content and chain floor) or a topology (by topology).
  struct Entry {
    std::shared_ptr<const PatchSet> patches;
    std::shared_ptr<const MeshTopology> topology;
  };

  LruCache<std::string, Entry> cache_;
  SingleFlight<std::string, PatchSet, TesseraError> builds_;
  SingleFlight<std::string, MeshTopology, TesseraError> topologyBuilds_;
  // Topologies preprocessed once (their keys only): the second sees its topology kept.
  static constexpr size_t kSeenEntryBytes = 64;
  LruCache<std::string, char> seen_{1 << 20};
  std::atomic<uint64_t> topologyHits_{0};
  std::atomic<uint64_t> topologyMisses_{0};
  int64_t maxRefinedVertices_;
  std::atomic<uint64_t> hits_{0};
  std::atomic<uint64_t> misses_{0};
};

}  // namespace tessera::server
