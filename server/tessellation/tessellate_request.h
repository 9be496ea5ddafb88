// Checks a TessellateRequest against the API's rules and the server's budgets and turns it into
// a TessellationJob. Refusals name the field: INVALID_ARGUMENT for values that make no sense
// (zero, negative, NaN, infinite, out of range), RESOURCE_EXHAUSTED for sensible values past a
// budget (a tolerance finer than the server allows, too many triangles or pixels).
#pragma once

#include <cstdint>

#include "server/calls/accuracy_limits.h"
#include "server/meshes/mesh_metadata.h"
#include "server/tessellation/tessellation_engine.h"
#include "tessera/v1/tessellation.pb.h"

namespace tessera::server {

// What can be checked without the mesh; run before looking the mesh up.
void checkTessellateRequest(const tessera::v1::TessellateRequest& request,
                            const TessellationLimits& limits);

// The job for request on the mesh described by metadata (whose bounding box scales relative
// tolerances and bounds absolute ones). Expects checkTessellateRequest to have passed.
TessellationJob planTessellationJob(const tessera::v1::TessellateRequest& request,
                                    const MeshMetadata& metadata, const TessellationLimits& limits);

}  // namespace tessera::server
