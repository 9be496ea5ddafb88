// The remote form of `tessera tessellate`: asks a tessera-server to tessellate a stored mesh
// (named "meshes/ID") and writes the streamed GLB to a file, checked against the server's
// checksum before it is put in place.
//
// The local `tessellate MODEL.obj` owns the subcommand (client/local_commands.cpp); its callback
// hands arguments that name a stored mesh (isRemoteMeshName) to runRemoteTessellate() with its
// own flags, so both forms read alike:
//   context.exitCode = isRemoteMeshName(flags->model) ? runRemoteTessellate(root, *flags)
//                                                     : runLocalTessellate(*flags);
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "client/remote_connection.h"

namespace tessera::cli {

struct TessellateFlags;  // client/camera_flags.h

// Everything a remote tessellation needs, as plain values (`tessera bench` fills these too).
struct RemoteTessellateArgs {
  std::string meshName;              // "meshes/ID"
  std::optional<double> tolerance;   // absolute, or relative with `relative`; unset: level only
  bool relative = false;
  std::optional<double> eta;
  std::optional<int> level;          // uniform tessellation level
  std::optional<int64_t> maxTriangles;
  std::string encoding;              // "float", "quantized", "meshopt"; empty: the server's default
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

// Runs the remote tessellation; returns the exit code (client/commands.h) after printing any
// error to stderr. The endpoint comes from the --server/--token/... options parsed on root.
int runRemoteTessellate(const RemoteEndpoint& endpoint, const RemoteTessellateArgs& args);
int runRemoteTessellate(const CLI::App& root, const RemoteTessellateArgs& args);
// The same with the local command's flags (flags.model = "meshes/ID"); a tolerance of 0, a
// level of 0 and an empty --eye mean "not given", as they do locally.
int runRemoteTessellate(const CLI::App& root, const TessellateFlags& flags);

}  // namespace tessera::cli
