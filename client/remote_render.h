// `tessera render`: asks a tessera-server to render a stored mesh (RenderService.Render) and
// writes each frame to a file, checked against the server's size and SHA-256 before it is put
// in place.
//
//   tessera --server 127.0.0.1:50051 render meshes/bigguy --eye 0,2,40 --target 0,2,0
//       --size 1280x720 --pixel-accuracy 0.5 -o bigguy.png
//   tessera render meshes/bigguy --eye 0,2,40 --target 0,2,0 --turntable 36 -o spin.png
//       # spin-000.png ... spin-035.png: 36 cameras orbiting the target about the up axis
//
// The camera flags read as in `tessellate` (client/camera_flags.h): --eye, --target, --up,
// --fov, --size, --pixel-accuracy, --tolerance, --level, --eta, --max-triangles.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "client/commands.h"
#include "client/remote_connection.h"

namespace tessera::cli {

struct RemoteRenderArgs {
  std::string mesh;  // "meshes/ID" or "ID"
  std::string eye, target, up = "0,1,0";
  double fovDeg = 45;
  std::string size = "1280x720";
  std::optional<double> pixelAccuracy;  // at most one of these three; none: 0.5 pixel
  std::optional<double> tolerance;
  std::optional<int> level;
  std::optional<double> eta;
  std::optional<long long> maxTriangles;
  std::string format;          // png|jpeg|exr|raw; empty: from the output's extension
  std::optional<int> quality;  // JPEG
  bool noCrackFilling = false;
  int turntable = 0;   // > 0: this many cameras around the up axis
  std::string output;  // the file, or the pattern with --turntable
  std::optional<int> timeoutSeconds;
};

// The file frame `index` of `count` is written to: `output` itself for a single camera;
// otherwise `output` with "%d"/"%03d"-style placeholder filled in, or "-NNN" (at least three
// digits) inserted before its extension. Throws std::invalid_argument for a bad pattern.
std::string frameFileName(const std::string& output, int index, int count);

// Runs the render; returns the exit code (client/commands.h) after printing any error.
int runRemoteRender(const RemoteEndpoint& endpoint, const RemoteRenderArgs& args);

// Adds `render` to app (which must have the endpoint options, client/remote_connection.h).
void registerRenderCommand(CLI::App& app, CommandContext& context);

}  // namespace tessera::cli
