// runRemoteTessellate() for the flags of the local `tessellate` command (client/camera_flags.h),
// so that `tessera tessellate meshes/ID ...` takes exactly the flags the local form takes.
#include "client/camera_flags.h"
#include "client/remote_tessellate.h"

namespace tessera::cli {
namespace {

bool flagGiven(const CLI::App& root, const std::string& flag) {
  for (const CLI::App* sub : root.get_subcommands()) {
    const CLI::Option* option = sub->get_name() == "tessellate" ? sub->get_option_no_throw(flag) : nullptr;
    if (option && option->count() > 0) return true;
  }
  return false;
}

}  // namespace

int runRemoteTessellate(const CLI::App& root, const TessellateFlags& flags) {
  RemoteTessellateArgs args;
  args.meshName = flags.model;
  args.output = flags.output;
  if (flags.tolerance != 0) args.tolerance = flags.tolerance;
  args.relative = flags.relative;
  args.eta = flags.eta;
  if (flags.level != 0) args.level = flags.level;
  // Only when given: the local default budget may exceed what the server allows.
  if (flagGiven(root, "--max-triangles")) args.maxTriangles = flags.maxTriangles;
  args.encoding = flags.encoding;
  // The local flags give the camera's up, field of view and size defaults; --eye turns it on.
  if (!flags.eye.empty() || !flags.target.empty()) {
    args.eye = flags.eye;
    args.target = flags.target;
    args.up = flags.up;
    args.fovDeg = flags.fov;
    args.size = flags.size;
    args.pixelAccuracy = flags.pixelAccuracy;
  }
  return runRemoteTessellate(root, args);
}

}  // namespace tessera::cli
