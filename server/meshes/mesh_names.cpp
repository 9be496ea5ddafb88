#include "server/meshes/mesh_names.h"

#include <fmt/format.h>

#include "server/calls/status_error.h"

namespace tessera::server {
namespace {

constexpr size_t kMaxMeshIdLength = 63;
constexpr std::string_view kIdRule = "^[a-z0-9][a-z0-9-]{0,62}$";

bool isIdStart(char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'); }
bool isIdChar(char c) { return isIdStart(c) || c == '-'; }

}  // namespace

bool isValidMeshId(std::string_view id) {
  if (id.empty() || id.size() > kMaxMeshIdLength || !isIdStart(id.front())) return false;
  for (char c : id) {
    if (!isIdChar(c)) return false;
  }
  return true;
}

void requireMeshId(std::string_view id, std::string_view field) {
  if (id.empty()) throwInvalidArgument(fmt::format("{}: a mesh id is required", field));
  if (!isValidMeshId(id)) {
    throwInvalidArgument(fmt::format("{}: {} is not a valid mesh id (must match {})", field,
                                     quoteForMessage(id), kIdRule));
  }
}

std::string meshIdFromName(std::string_view name, std::string_view field) {
  if (name.empty()) {
    throwInvalidArgument(fmt::format("{}: a mesh name \"meshes/{{id}}\" is required", field));
  }
  if (name.substr(0, kMeshNamePrefix.size()) != kMeshNamePrefix) {
    throwInvalidArgument(fmt::format("{}: {} is not a mesh name (expected \"meshes/{{id}}\")",
                                     field, quoteForMessage(name)));
  }
  std::string_view id = name.substr(kMeshNamePrefix.size());
  if (!isValidMeshId(id)) {
    throwInvalidArgument(fmt::format("{}: {} has an invalid mesh id (must match {})", field,
                                     quoteForMessage(name), kIdRule));
  }
  return std::string(id);
}

std::string meshName(std::string_view id) { return std::string(kMeshNamePrefix) + std::string(id); }

}  // namespace tessera::server
