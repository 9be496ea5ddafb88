// The remote form of `tessera tessellate`: asks a tessera-server to tessellate a stored mesh
// (named "meshes/ID") and writes the streamed GLB to a file, checked against the server's
// checksum before it is put in place.
//
// The local `tessellate MODEL.obj` shares the subcommand name. Whoever registers `tessellate`
// hands arguments that name a stored mesh (isRemoteMeshName) to runRemoteTessellate():
//   - registerRemoteCommands() registers it itself when no local `tessellate` exists yet;
//   - otherwise the local command's callback calls runRemoteTessellate(root, args), having bound
//     the remote-only flags with addRemoteTessellateOptions() (it skips flags already defined,
//     so the local command's own --tolerance, -o and so on must then be copied into args).
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "client/remote_connection.h"

namespace tessera::cli {

struct RemoteTessellateArgs {
  std::string meshName;              // "meshes/ID"
  std::optional<double> tolerance;   // absolute, or relative with `relative`
  bool relative = false;
  std::optional<double> eta;
  std::optional<int> level;          // uniform tessellation level
  std::optional<int64_t> maxTriangles;
  // View-dependent tolerance: all of eye, target, up, fov and size, or none.
  std::string eye, target, up;       // "X,Y,Z"
  std::optional<double> fovDeg;
  std::string size;                  // "WxH"
  std::optional<double> pixelAccuracy;
  std::string output;                // the .glb to write
  std::optional<int> timeoutSeconds;
};

// True when a `tessellate` argument names a stored mesh rather than a local file.
bool isRemoteMeshName(std::string_view argument);

// Adds --tolerance, --relative, --eta, --level, --max-triangles, --eye, --target, --up, --fov,
// --size, --pixel-accuracy, -o/--output and --timeout to sub, skipping any sub already has.
void addRemoteTessellateOptions(CLI::App& sub, RemoteTessellateArgs& args);

// Runs the remote tessellation with the endpoint options parsed on root; returns the exit code
// (client/commands.h) after printing any error to stderr.
int runRemoteTessellate(const CLI::App& root, const RemoteTessellateArgs& args);
int runRemoteTessellate(const RemoteEndpoint& endpoint, const RemoteTessellateArgs& args);

}  // namespace tessera::cli
