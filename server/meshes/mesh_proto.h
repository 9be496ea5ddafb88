// Translation between the server's mesh types and tessera.v1 messages.
#pragma once

#include <functional>
#include <string>

#include "core/mesh/control_mesh.h"
#include "server/meshes/mesh_metadata.h"
#include "tessera/v1/mesh.pb.h"

namespace tessera::server {

void toProto(const MeshMetadata& metadata, tessera::v1::Mesh* out);

// ListMeshes page tokens: opaque to clients, the last id of the previous page inside.
std::string encodePageToken(const std::string& lastId);
// Throws StatusError(INVALID_ARGUMENT) naming page_token when the token was not made by
// encodePageToken.
std::string decodePageToken(const std::string& token);

// Splits mesh into MeshArrays messages of at most about maxBytes each, in upload order, and hands
// each to emit; stops early when emit returns false. Returns false if it stopped early.
bool forEachArraysChunk(const ControlMesh& mesh, size_t maxBytes,
                        const std::function<bool(const tessera::v1::MeshArrays&)>& emit);

}  // namespace tessera::server
