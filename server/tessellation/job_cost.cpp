#include "server/tessellation/job_cost.h"

#include <algorithm>
#include <cmath>

#include "core/pipeline/glb_output.h"
#include "core/pipeline/preprocessing.h"
#include "core/request/tessellation_options.h"

namespace tessera::server {
namespace {

std::string keyOf(const std::string& meshSha256, const JobShape& shape) {
  return meshSha256 + (shape.uniform ? "/uniform" : shape.singlePhase ? "/single-phase" : "/tolerance");
}

// Triangles = coefficient × scale(shape); an estimate takes the smallest tolerance a quantizing
// job can plan to, a record the tolerance asked.
double scaleOf(const JobShape& shape, bool estimate) {
  if (shape.uniform) return double(shape.level) * double(shape.level);
  const double planned = shape.relativeTolerance * (estimate && shape.quantizing ? 1 - kQuantizationShare : 1);
  return planned > 0 ? 1.0 / planned : 0.0;
}

}  // namespace

JobShape shapeOf(const ControlMesh& mesh, const TessellationJob& job) {
  if (job.accuracy.uniform()) return {true, job.accuracy.level, 0};
  TessellationOptions options;
  options.accuracy = job.accuracy;
  options.camera = job.camera;
  JobShape shape{false, 0, finestRelativeTolerance(mesh, options)};
  shape.quantizing = job.encoding != GlbEncoding::kFloat;
  shape.singlePhase = job.eta == 0;
  shape.camera = job.camera.has_value();
  return shape;
}

void TessellationCosts::record(const std::string& meshSha256, const JobShape& shape, int64_t triangles) {
  if (shape.camera) return;  // its coefficient would under-estimate a tolerance job (job_cost.h)
  const double scale = scaleOf(shape, false);
  if (!(scale > 0) || !std::isfinite(scale)) return;
  const double coefficient = double(triangles) / scale;
  const std::string key = keyOf(meshSha256, shape);
  std::lock_guard lock(mutex_);
  auto [it, added] = coefficients_.try_emplace(key, coefficient);
  if (!added) {
    it->second = std::max(it->second, coefficient);
    return;
  }
  order_.push_back(key);
  if (order_.size() > maxEntries_) {
    coefficients_.erase(order_.front());
    order_.pop_front();
  }
}

std::optional<double> TessellationCosts::estimate(const std::string& meshSha256, const JobShape& shape) const {
  const double scale = scaleOf(shape, true);
  if (!(scale > 0)) return std::nullopt;
  std::lock_guard lock(mutex_);
  auto it = coefficients_.find(keyOf(meshSha256, shape));
  if (it == coefficients_.end()) return std::nullopt;
  return it->second * scale;
}

}  // namespace tessera::server
