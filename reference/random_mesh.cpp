#include "reference/random_mesh.h"

#include <random>

#include "core/base/error.h"
#include "core/pipeline/preprocessing.h"
#include "reference/limit_surface.h"

namespace tessera::testing {

ControlMesh randomMesh(uint32_t seed) {
  std::mt19937 random(seed);
  ControlMesh mesh;
  const int vertices = 4 + int(random() % 12);
  for (int i = 0; i < vertices; ++i) {
    mesh.positions.emplace_back(float(random() % 100) / 10, float(random() % 100) / 10, float(random() % 100) / 10);
  }
  const int faces = 1 + int(random() % 10);
  for (int f = 0; f < faces; ++f) {
    const int size = 3 + int(random() % 3);
    mesh.faceSizes.push_back(size);
    for (int k = 0; k < size; ++k) mesh.faceVertices.push_back(int(random() % uint32_t(vertices)));
  }
  if (random() % 3 == 0) mesh.holes.push_back(int(random() % uint32_t(faces)));
  if (random() % 4 == 0) mesh.rules.boundary = BoundaryInterpolation::kEdgeAndCorner;
  if (random() % 3 == 0) {
    const int f = int(random() % uint32_t(faces));
    int first = 0;
    for (int g = 0; g < f; ++g) first += mesh.faceSizes[g];
    const int a = mesh.faceVertices[first], b = mesh.faceVertices[first + 1];
    if (a != b) mesh.creases.push_back({a, b, float(random() % 30) / 2});
  }
  return mesh;
}

TessellationResult tessellateRandom(const ControlMesh& mesh, double relative) {
  validateControlMesh(mesh);
  const PatchSet patches = buildPatchSet(mesh);
  TessellationOptions options;
  options.accuracy = Accuracy::relative(relative);
  options.recordParameters = true;
  return tessellate(patches, mesh, options);
}

RandomMeshCheck checkRandomMesh(uint32_t seed, double relative) {
  RandomMeshCheck check;
  const ControlMesh mesh = randomMesh(seed);
  TessellationResult result;
  try {
    result = tessellateRandom(mesh, relative);
  } catch (const TesseraError& error) {
    check.refused = error.what();
    return check;
  }
  check.empty = result.mesh.triangleCount() == 0;
  if (check.empty) return check;
  const LimitSurface far(mesh, LimitSurface::Backend::kFar);
  check.tolerance = (relative + LimitSurface::kRelativeAccuracy) * far.diagonal();
  LimitDistanceOptions options;
  options.everyDomainBeyond = check.tolerance;
  check.report = measureLimitDistance(far, viewOf(result.mesh), options);
  return check;
}

}  // namespace tessera::testing
