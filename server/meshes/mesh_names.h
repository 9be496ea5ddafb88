// Mesh ids and resource names ("meshes/{id}"), checked once here so that every RPC refuses a bad
// name with the same INVALID_ARGUMENT message naming the field.
#pragma once

#include <string>
#include <string_view>

namespace tessera::server {

inline constexpr std::string_view kMeshNamePrefix = "meshes/";

// ^[a-z0-9][a-z0-9-]{0,62}$: safe in URLs, file names and SQL identifiers alike.
bool isValidMeshId(std::string_view id);

// Throws StatusError(INVALID_ARGUMENT) naming `field` unless id is valid.
void requireMeshId(std::string_view id, std::string_view field);

// "meshes/{id}" -> id; throws StatusError(INVALID_ARGUMENT) naming `field` otherwise.
std::string meshIdFromName(std::string_view name, std::string_view field);

std::string meshName(std::string_view id);

}  // namespace tessera::server
