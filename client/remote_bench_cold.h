// The cold mix of `tessera bench --cold N` (issue 46): each request uploads a mesh whose content
// the server has never seen and tessellates it once, so that the Tessellate pays for
// preprocessing (Far's refinement, the patches, the surface tree) as a mesh's first one does.
// The meshes are copies of the stored meshes the run names (remote_cold_copies.h), numbered
// from the seed and the copy's index, uploaded as meshes/bench-cold-SEED-INDEX. They stay in the
// store: a second run with the same seed is then refused ALREADY_EXISTS, where deleting them
// would let it pass with copies the server's patch-set cache still holds, served warm.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "client/remote_bench_runner.h"
#include "client/remote_cold_copies.h"
#include "tessera/v1/tessellation.pb.h"

namespace tessera::cli {

std::string coldMeshId(int seed, int64_t index);

// Request i uploads copy firstIndex + i of sources[k], k = (firstIndex + i) % sources.size(),
// and, if the upload succeeded, tessellates it once as requests[k] asks (under the copy's
// name): an upload call, then a tessellate call, each timed on its own (the tessellation from
// sending the request until the whole GLB has arrived and been checked).
PhaseRequest coldRequests(const std::vector<ColdSource>& sources,
                          const std::vector<tessera::v1::TessellateRequest>& requests, int seed,
                          int64_t firstIndex);

}  // namespace tessera::cli
