#include "server/tessellation/job_cost.h"

#include <algorithm>
#include <cmath>

#include "core/pipeline/preprocessing.h"
#include "core/request/tessellation_options.h"

namespace tessera::server {
namespace {

std::string keyOf(const std::string& meshSha256, const JobShape& shape) {
  return meshSha256 + (shape.uniform ? "/uniform" : "/tolerance");
}

// Triangles = coefficient × scale(shape).
double scaleOf(const JobShape& shape) {
  if (shape.uniform) return double(shape.level) * double(shape.level);
  return shape.relativeTolerance > 0 ? 1.0 / shape.relativeTolerance : 0.0;
}

}  // namespace

JobShape shapeOf(const ControlMesh& mesh, const TessellationJob& job) {
  if (job.accuracy.uniform()) return {true, job.accuracy.level, 0};
  TessellationOptions options;
  options.accuracy = job.accuracy;
  options.camera = job.camera;
  return {false, 0, finestRelativeTolerance(mesh, options)};
}

void TessellationCosts::record(const std::string& meshSha256, const JobShape& shape, int64_t triangles) {
  const double scale = scaleOf(shape);
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
  const double scale = scaleOf(shape);
  if (!(scale > 0)) return std::nullopt;
  std::lock_guard lock(mutex_);
  auto it = coefficients_.find(keyOf(meshSha256, shape));
  if (it == coefficients_.end()) return std::nullopt;
  return it->second * scale;
}

}  // namespace tessera::server
