// Watertightness checked on the mesh itself rather than on pixels: the sphere's tessellation,
// with vertices welded only where their positions are bit-identical, must be a closed,
// consistently oriented 2-manifold — every directed edge used exactly once and its reverse
// exactly once. A single T-junction or a one-ulp difference between the two sides of a shared
// edge leaves an unmatched edge.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <tuple>

#include "gpu/vulkan/patch_batches.h"
#include "render_test_support.h"
#include "two_patch_scenes.h"

namespace tessera::gpu::testing {
namespace {

using Key = std::tuple<uint32_t, uint32_t, uint32_t>;  // the position's float bits

// Directed edges of the welded mesh, counted.
std::map<std::pair<uint32_t, uint32_t>, int> weldedDirectedEdges(const TessellatedMesh& mesh) {
  std::map<Key, uint32_t> weld;
  std::vector<uint32_t> welded(mesh.vertexPatchIds.size());
  for (size_t i = 0; i < welded.size(); ++i) {
    uint32_t bits[3];
    std::memcpy(bits, &mesh.positions[3 * i], sizeof(bits));
    Key key{bits[0], bits[1], bits[2]};
    auto it = weld.emplace(key, static_cast<uint32_t>(weld.size())).first;
    welded[i] = it->second;
  }
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    for (int c = 0; c < 3; ++c) {
      uint32_t a = welded[mesh.indices[t + c]];
      uint32_t b = welded[mesh.indices[t + (c + 1) % 3]];
      edges[{a, b}] += 1;
    }
  }
  return edges;
}

size_t unmatchedEdges(const TessellatedMesh& mesh) {
  auto edges = weldedDirectedEdges(mesh);
  size_t bad = 0;
  for (const auto& [edge, count] : edges) {
    auto reverse = edges.find({edge.second, edge.first});
    bad += count != 1 || reverse == edges.end() || reverse->second != 1;
  }
  return bad;
}

TEST(WatertightMesh, SphereWithStitchedLevelsIsAClosedManifold) {
  Renderer renderer = makeTestRenderer();
  std::vector<RenderPatch> patches =
      makeSphere(Vec3d(0.1, 0.2, 0.3), 1.5, 3, hashedEdgeLevels(1, 24), 0);
  TessellatedMesh mesh = renderer.tessellate(patches);
  uint64_t expectedTriangles = 0;
  for (const RenderPatch& p : patches) expectedTriangles += patternTriangleCount(p.edgeLevels);
  ASSERT_EQ(mesh.indices.size(), 3 * expectedTriangles);
  EXPECT_EQ(unmatchedEdges(mesh), 0u);
  expectNoValidationMessages(renderer);
}

TEST(WatertightMesh, UniformLevelsAndSmallBatchesToo) {
  Renderer renderer = makeTestRenderer();
  std::vector<RenderPatch> patches = makeSphere(Vec3d(0, 0, 0), 1.0, 2, hashedEdgeLevels(1, 8), 0);
  for (uint32_t level : {1u, 2u, 7u, 64u}) {
    TessellatedMesh mesh = renderer.tessellate(patches, level);
    EXPECT_EQ(mesh.indices.size(), 3 * patches.size() * 2 * level * level) << level;
    EXPECT_EQ(unmatchedEdges(mesh), 0u) << level;
  }
}

TEST(WatertightMesh, MismatchedSharedEdgeLevelsAreDetected) {
  // The check must be able to fail: a seam with levels 2 and 7 leaves open boundary edges
  // along it (besides the square's own outer boundary, present either way).
  Renderer renderer = makeTestRenderer();
  size_t matched = unmatchedEdges(renderer.tessellate(twoPatchesWithCurvedSeam(0.4, 5, 5)));
  size_t mismatched = unmatchedEdges(renderer.tessellate(twoPatchesWithCurvedSeam(0.4, 2, 7)));
  EXPECT_EQ(mismatched, matched + 2 + 7);
}

// Distance from p to the patch surface: grid search, then Gauss-Newton on (u,v) in double.
double distanceToPatch(const RenderPatch& patch, const Vec3d& p) {
  double bu = 0, bv = 0, best = 1e300;
  for (int j = 0; j <= 16; ++j) {
    for (int i = 0; i <= 16; ++i) {
      double d = length(evalPatch(patch, i / 16.0, j / 16.0) - p);
      if (d < best) best = d, bu = i / 16.0, bv = j / 16.0;
    }
  }
  const double h = 1e-6;
  for (int iter = 0; iter < 20; ++iter) {
    Vec3d s = evalPatch(patch, bu, bv);
    Vec3d su = (evalPatch(patch, bu + h, bv) - evalPatch(patch, bu - h, bv)) * (0.5 / h);
    Vec3d sv = (evalPatch(patch, bu, bv + h) - evalPatch(patch, bu, bv - h)) * (0.5 / h);
    Vec3d r = p - s;
    double a = dot(su, su), b = dot(su, sv), c = dot(sv, sv);
    double det = a * c - b * b;
    if (det <= 0) break;
    double du = (c * dot(su, r) - b * dot(sv, r)) / det;
    double dv = (a * dot(sv, r) - b * dot(su, r)) / det;
    bu = std::clamp(bu + du, 0.0, 1.0);
    bv = std::clamp(bv + dv, 0.0, 1.0);
  }
  return length(evalPatch(patch, bu, bv) - p);
}

TEST(WatertightMesh, VerticesLieOnTheirPatchWithSurfaceNormals) {
  // Each vertex must be a point of its own patch (as evaluated independently on the CPU, in
  // double precision) up to float rounding, and carry a unit normal perpendicular to it.
  Renderer renderer = makeTestRenderer();
  std::vector<RenderPatch> patches =
      makeSphere(Vec3d(0.1, 0.2, 0.3), 1.5, 2, hashedEdgeLevels(1, 9), 0);
  TessellatedMesh mesh = renderer.tessellate(patches);
  ASSERT_FALSE(mesh.vertexPatchIds.empty());
  for (size_t i = 0; i < mesh.vertexPatchIds.size(); ++i) {
    ASSERT_LT(mesh.vertexPatchIds[i], patches.size());
    const RenderPatch& patch = patches[mesh.vertexPatchIds[i]];
    Vec3d p(mesh.positions[3 * i], mesh.positions[3 * i + 1], mesh.positions[3 * i + 2]);
    Vec3d n(mesh.normals[3 * i], mesh.normals[3 * i + 1], mesh.normals[3 * i + 2]);
    ASSERT_LT(distanceToPatch(patch, p), 2e-6) << "vertex " << i;  // ~10 ulp at radius 1.5
    ASSERT_NEAR(length(n), 1.0, 1e-5) << "vertex " << i;
    // Sphere-like patches: the surface normal is close to radial (either orientation).
    Vec3d radial = p - Vec3d(0.1, 0.2, 0.3);
    ASSERT_GT(std::abs(dot(n, radial)) / length(radial), 0.98) << "vertex " << i;
  }
}

}  // namespace
}  // namespace tessera::gpu::testing
