// The flags of `tessera tessellate` (and later `render`), shared by the local and remote forms:
// tolerance, η, uniform level, and a camera that makes the tolerance pixel-accurate.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "core/request/tessellation_options.h"

namespace tessera::cli {

struct TessellateFlags {
  std::string model;   // OBJ path, or meshes/NAME for the remote form
  std::string output;  // .glb
  double tolerance = 0;
  bool relative = false;
  double eta = 0.5;
  int level = 0;
  std::string eye, target, up = "0,1,0", size = "1920x1080";
  double fov = 45;
  double pixelAccuracy = 0.5;
  long long maxTriangles = 20'000'000;
  std::string encoding = "float";  // GLB encoding: float, quantized or meshopt (core/output/glb_writer.h)

  void addTo(CLI::App& command);
  // Throws TesseraError (kInvalidInput) naming the flag for malformed values.
  TessellationOptions toOptions() const;
};

}  // namespace tessera::cli
