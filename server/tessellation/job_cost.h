// Scheduling by cost (server/README.md): what a Tessellate will make, estimated before it is
// admitted, so that a short job can take the light lane (admission_control.h) instead of waiting
// behind long ones. A job is light when its mesh's content is already preprocessed at the depth
// it needs (no preprocessing, the cold path's cost) and its output is estimated small.
//
// The estimate scales what the last job on the same content made: an adaptive tessellation's
// triangles grow as 1/ε (a tile's grid rates go as √(curvature/ε) in each direction,
// docs/ADAPTIVE.md §2), a uniform one's as level² (about `level` samples along each side of a
// base face, core/uniform/uniform_levels.h). A content never tessellated has no estimate
// and takes the main lane; the scale errs towards more triangles at finer tolerances (a coarse
// job's floor of two triangles a face inflates its coefficient).
//
// What would make an estimate small when the job is not (each closed here, job_cost_test.cpp):
// - η = 0 runs another path (the paper's single-phase baseline, core/pipeline/tessellate.h) that
//   makes 1.5-7 times the adaptive path's triangles (bigguy: 19,562 against 2,900 at 1e-2):
//   it has its own coefficients.
// - A pixel-accurate job is coarser away from the camera than its finest tolerance: its
//   coefficient would under-estimate a tolerance job, so it records none; it is estimated from the
//   tolerance jobs' coefficient at its finest tolerance, which over-estimates it.
// - A quantized or meshopt job plans to ε less the grid's error, up to kQuantizationShare of it:
//   it is estimated at that smaller tolerance (and records at its ε, erring high for the others).
// Frames (Render) always take the main lane, so they need no estimate here.
#pragma once

#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>

#include "core/mesh/control_mesh.h"
#include "server/tessellation/tessellation_engine.h"

namespace tessera::server {

// What sets a job's size: a uniform level, or the finest tolerance it asks anywhere on the mesh
// as a fraction of the diagonal (core's finestRelativeTolerance: with a camera, at the mesh's
// nearest point, which overestimates a pixel request's triangles).
struct JobShape {
  bool uniform = false;
  int level = 0;
  double relativeTolerance = 0;
  bool singlePhase = false;  // η = 0: the single-phase path, its own coefficients
  bool camera = false;       // pixel accuracy: estimated from the tolerance jobs', records none
  bool quantizing = false;   // quantized or meshopt: planned to up to kQuantizationShare less
};

JobShape shapeOf(const ControlMesh& mesh, const TessellationJob& job);

// Per content and mode, the coefficient of the last jobs (the largest seen, to err high), for at
// most `maxEntries` contents (the oldest forgotten first). Thread-safe.
class TessellationCosts {
 public:
  explicit TessellationCosts(size_t maxEntries = 4096) : maxEntries_(maxEntries) {}

  void record(const std::string& meshSha256, const JobShape& shape, int64_t triangles);
  // The triangles a job of `shape` on this content would make; nullopt when none was recorded.
  std::optional<double> estimate(const std::string& meshSha256, const JobShape& shape) const;

 private:
  const size_t maxEntries_;
  mutable std::mutex mutex_;
  std::unordered_map<std::string, double> coefficients_;
  std::deque<std::string> order_;  // keys, first recorded first
};

}  // namespace tessera::server
