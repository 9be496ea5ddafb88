// Checks a TessellateRequest against the API's rules and the server's budgets and turns it into
// a TessellationJob. Refusals name the field: INVALID_ARGUMENT for values that make no sense
// (zero, negative, NaN, infinite, out of range) and for an accuracy finer than the server ever
// serves (min_relative_tolerance, in every mode; min_pixel_accuracy), which no retry changes;
// RESOURCE_EXHAUSTED for a request past a work budget (max_triangles, too many pixels).
#pragma once

#include <cstdint>

#include "server/calls/accuracy_limits.h"
#include "server/meshes/mesh_metadata.h"
#include "server/tessellation/tessellation_engine.h"
#include "tessera/v1/tessellation.pb.h"

namespace tessera::server {

// Every check that needs no mesh, each run once, and the job as far as the request alone makes
// it: a tolerance still as asked (absolute or relative). Run before looking the mesh up.
TessellationJob checkTessellateRequest(const tessera::v1::TessellateRequest& request,
                                       const TessellationLimits& limits);

// The job on the mesh `metadata` describes: a tolerance turned into model units against the
// mesh's bounding box and checked against it and the server's limits (toleranceOnMesh), and the
// mesh's id and content hash.
void placeOnMesh(TessellationJob& job, const MeshMetadata& metadata, const TessellationLimits& limits);

// The job on the mesh's positions, once it is loaded and before any preprocessing: a pixel
// accuracy held to min_relative_tolerance where it asks the most, at the mesh's nearest point
// (checkPixelsOnMesh), as placeOnMesh holds a tolerance.
void checkOnMesh(const TessellationJob& job, const ControlMesh& mesh, const TessellationLimits& limits);

}  // namespace tessera::server
