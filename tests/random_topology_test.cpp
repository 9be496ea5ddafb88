// Random control meshes, the topologies nobody models on purpose but uploads happen to contain:
// 4–15 vertices, 1–10 faces of 3–5 random corners (so faces that repeat a vertex, fold back along
// an edge they left by, collapse an edge to a point, meet an edge twice, and non-manifold edges
// and vertices), random holes, boundary rules and a crease. Every mesh Tessera accepts is
// tessellated within ε of OpenSubdiv's limit surface, two-sided, at 1e-2 of the diagonal. The
// reference is Far's patch table of the input (Debian's Bfr 3.5.0 mis-evaluates, and once
// crashes on, such input). docs/NONMANIFOLD.md has what 2,000 seeds give; this keeps the first
// 400 for time.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "core/error.h"
#include "core/patch_set.h"
#include "core/tessellate.h"
#include "tests/support/limit_distance.h"
#include "tests/support/limit_surface.h"

namespace tessera {
namespace {

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

TEST(RandomTopology, EveryAcceptedMeshIsTessellatedWithinTolerance) {
  constexpr double kRelative = 1e-2;
  int measured = 0, refused = 0, empty = 0;
  for (uint32_t seed = 0; seed < 400; ++seed) {
    SCOPED_TRACE("random mesh " + std::to_string(seed));
    const ControlMesh mesh = randomMesh(seed);
    TessellationResult result;
    try {
      validateControlMesh(mesh);
      const PatchSet patches = buildPatchSet(mesh);
      TessellationOptions options;
      options.accuracy = Accuracy::relative(kRelative);
      options.recordParameters = true;
      result = tessellate(patches, mesh, options);
    } catch (const TesseraError&) {
      ++refused;
      continue;
    }
    if (result.mesh.triangleCount() == 0) {
      ++empty;  // every face a hole
      continue;
    }
    const testing::LimitSurface far(mesh, testing::LimitSurface::Backend::kFar);
    const testing::LimitDistanceReport report = testing::measureLimitDistance(far, testing::viewOf(result.mesh));
    EXPECT_LE(report.twoSided(), (kRelative + testing::LimitSurface::kRelativeAccuracy) * report.diagonal)
        << "at face " << report.twoSidedAt().face << "/" << report.twoSidedAt().subFace << " ("
        << report.twoSidedAt().u << ", " << report.twoSidedAt().v << ")";
    ++measured;
  }
  std::printf("%d random meshes measured, %d refused, %d all holes\n", measured, refused, empty);
  EXPECT_GE(measured, 380);
}

}  // namespace
}  // namespace tessera
