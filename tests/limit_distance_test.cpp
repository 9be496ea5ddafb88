// The measured distance to the limit surface (reference/limit_distance.h) and what it is built
// from, checked against expectations derived by hand: O(1/R²) convergence of a uniform
// tessellation, a vertex moved by a known offset, a planar limit surface measured at zero, and the
// AABB tree against brute force.
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "core/mesh/obj_reader.h"
#include "reference/limit_distance.h"
#include "reference/limit_projection.h"
#include "reference/models.h"
#include "reference/triangle_bvh.h"
#include "reference/uniform_tessellation.h"

namespace tessera {
namespace {

using testing::LimitDistanceReport;
using testing::LimitSurface;
using testing::UniformTessellation;

ControlMesh shape(const std::string& name) {
  return readObjFile(testing::modelsDir() + "/opensubdiv-shapes/" + name + ".obj");
}

Vec3d normalized(const Vec3d& v) {
  return v * (1.0 / length(v));
}

// A flat n×n grid of unit quads whose boundary corners are sharp: its limit surface is exactly the
// square [0, n]² (the boundary curves are B-splines of collinear, evenly spaced points).
ControlMesh flatGrid(int n) {
  ControlMesh mesh;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) mesh.positions.push_back(Vec3(float(i), float(j), 0.0f));
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int v = j * (n + 1) + i;
      mesh.faceSizes.push_back(4);
      mesh.faceVertices.insert(mesh.faceVertices.end(), {v, v + 1, v + n + 2, v + n + 1});
    }
  }
  mesh.rules.boundary = BoundaryInterpolation::kEdgeAndCorner;
  return mesh;
}

TEST(LimitDistanceTest, UniformCubeTessellationConvergesQuadratically) {
  const LimitSurface surface(shape("catmark_cube"));
  const LimitDistanceReport at16 =
      measureLimitDistance(surface, tessellateUniform(surface, 16).view());
  const LimitDistanceReport at32 =
      measureLimitDistance(surface, tessellateUniform(surface, 32).view());
  // Interpolating a C² surface at spacing h errs by ~h²·|f''|/8: a quarter when h halves. The
  // cube's extraordinary corners may slow that a little, never speed it up past 4.
  EXPECT_LT(at32.twoSidedRelative(), 3e-4);
  EXPECT_GT(at32.twoSidedRelative(), 1e-6);  // a real distance, not a degenerate zero
  EXPECT_GT(at16.twoSided() / at32.twoSided(), 3.0);
  EXPECT_LT(at16.twoSided() / at32.twoSided(), 4.6);
  EXPECT_EQ(at32.meshSamples, 12u * 6u * 2u * 32u * 32u);  // K = 4: 12 points per triangle
  EXPECT_EQ(at32.limitSamples, 6u * 16u * 16u);
}

// The mesh vertex nearest to x.
uint32_t vertexAt(const UniformTessellation& mesh, const Vec3d& x) {
  uint32_t nearest = 0;
  for (uint32_t i = 1; i < mesh.positions.size(); ++i) {
    if (length(Vec3d(mesh.positions[i]) - x) < length(Vec3d(mesh.positions[nearest]) - x)) {
      nearest = i;
    }
  }
  return nearest;
}

TEST(LimitDistanceTest, VertexMovedOffAPlanarLimitSurfaceIsMeasuredAtItsOffset) {
  const LimitSurface surface(flatGrid(4));
  UniformTessellation mesh = tessellateUniform(surface, 8);
  EXPECT_LT(measureLimitDistance(surface, mesh.view()).twoSided(), 1e-9);  // points of the plane
  // Control vertex (2, 2) is interior, its limit point is (2, 2, 0) and a corner of four face
  // domains (so a limit sample). Raise its mesh vertex by d along the normal z.
  const uint32_t moved = vertexAt(mesh, Vec3d(2, 2, 0));
  ASSERT_LT(length(Vec3d(mesh.positions[moved]) - Vec3d(2, 2, 0)), 1e-6);
  const double h = 1.0 / 8, d = h / 10;
  mesh.positions[moved].z = float(d);
  const LimitDistanceReport report = measureLimitDistance(surface, mesh.view());
  // mesh -> limit: the samples nearest the vertex, barycentric (3/4, 1/4, 0) for K = 4, rose 3d/4.
  EXPECT_NEAR(report.meshToLimit, 0.75 * d, 1e-7);
  // limit -> mesh: from (2, 2, 0) to the raised fan, whose triangles' far edges lie at a horizontal
  // distance ρ of h (legs) or h/√2 (diagonals): d·ρ/√(ρ² + d²), between 0.9901·d and 0.9950·d.
  EXPECT_GE(report.limitToMesh, d * (h / std::sqrt(2.0)) / std::sqrt(h * h / 2 + d * d) - 1e-7);
  EXPECT_LE(report.limitToMesh, d * h / std::sqrt(h * h + d * d) + 1e-7);
  Vec3d worst;
  const testing::SurfaceLocation& at = report.limitToMeshAt;
  surface.evaluate(surface.domainOf(at.face, at.subFace), at.u, at.v, worst);
  EXPECT_LT(length(worst - Vec3d(2, 2, 0)), 1e-9)
      << "face " << at.face << " (" << at.u << ", " << at.v << ")";
}

TEST(LimitDistanceTest, VertexMovedOffACurvedLimitSurfaceIsMeasuredAtItsOffset) {
  const LimitSurface surface(shape("catmark_cube"));
  UniformTessellation mesh = tessellateUniform(surface, 32);
  const double baseline = measureLimitDistance(surface, mesh.view()).twoSided();
  // The mesh vertex at the limit point of control vertex 0 (corner (0, 0) of face 0's domain), an
  // extraordinary vertex of valence 3, moved outwards along the limit normal by 10x the baseline.
  Vec3d corner, du, dv;
  surface.evaluate(surface.domainOf(0, -1), 0, 0, corner, &du, &dv);
  const uint32_t moved = vertexAt(mesh, corner);
  ASSERT_LT(length(Vec3d(mesh.positions[moved]) - corner), 1e-6);
  Vec3d normal = normalized(cross(du, dv));
  if (dot(normal, corner) < 0) normal = normal * -1.0;  // the cube is centred on the origin
  const double d = 10 * baseline;
  mesh.positions[moved] = Vec3(corner + normal * d);
  const LimitDistanceReport report = measureLimitDistance(surface, mesh.view());
  // As on the plane (3d/4 and ~0.99·d), give or take the baseline and the spike's slope.
  EXPECT_GE(report.limitToMesh, 0.97 * d - baseline);
  EXPECT_LE(report.limitToMesh, d + baseline);
  EXPECT_GE(report.meshToLimit, 0.75 * d * 0.97 - baseline);
  EXPECT_LE(report.meshToLimit, 0.75 * d + baseline);
  Vec3d worst;
  const testing::SurfaceLocation& at = report.limitToMeshAt;
  surface.evaluate(surface.domainOf(at.face, at.subFace), at.u, at.v, worst);
  EXPECT_LT(length(worst - corner), 1e-6)
      << "face " << at.face << " (" << at.u << ", " << at.v << ")";
}

TEST(LimitDistanceTest, DenseSamplesOfTheSurfaceAreMeasuredTinyWithAndWithoutParameters) {
  const LimitSurface surface(shape("catmark_cube"));
  const UniformTessellation dense = tessellateUniform(surface, 64);
  const LimitDistanceReport withParameters = measureLimitDistance(surface, dense.view());
  testing::TriangleMeshView
      bare;  // positions and triangles only: every seed comes from the kd-tree
  bare.positions = dense.positions;
  bare.indices = dense.indices;
  const LimitDistanceReport withoutParameters = measureLimitDistance(surface, bare);
  EXPECT_LT(withParameters.twoSidedRelative(), 1e-4);
  EXPECT_NEAR(withoutParameters.meshToLimit, withParameters.meshToLimit,
              1e-3 * withParameters.meshToLimit);
  EXPECT_EQ(withoutParameters.limitToMesh, withParameters.limitToMesh);
}

TEST(LimitDistanceTest, TrianglesOfAPlanarLimitSurfaceAreAtZero) {
  const ControlMesh grid = flatGrid(4);
  const LimitSurface surface(grid);
  const std::vector<Vec3> square = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}};
  const std::vector<uint32_t> triangles = {0, 1, 2, 0, 2, 3};
  testing::TriangleMeshView view;
  view.positions = square;
  view.indices = triangles;
  const LimitDistanceReport report = measureLimitDistance(surface, view);
  EXPECT_LT(report.twoSided(), 1e-9);
  // Lifting corner (4, 4) by 0.5 tilts both triangles: the samples at barycentric 3/4 of it rise
  // to 0.375 over the square, and the limit corner lies 2/√16.25 below their planes.
  const std::vector<Vec3> lifted = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0.5f}, {0, 4, 0}};
  view.positions = lifted;
  const LimitDistanceReport liftedReport = measureLimitDistance(surface, view);
  EXPECT_NEAR(liftedReport.meshToLimit, 0.375, 1e-9);
  EXPECT_NEAR(liftedReport.limitToMesh, 2 / std::sqrt(16.25), 1e-9);
}

// Options out of range are refused with a message naming the ranges, not measured with.
TEST(LimitDistanceTest, RefusesOptionsOutOfRange) {
  const LimitSurface surface(flatGrid(2));
  const std::vector<Vec3> square = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
  const std::vector<uint32_t> triangles = {0, 1, 2, 0, 2, 3};
  testing::TriangleMeshView view;
  view.positions = square;
  view.indices = triangles;
  auto refused = [&](const testing::LimitDistanceOptions& options) {
    try {
      measureLimitDistance(surface, view, options);
    } catch (const std::invalid_argument& error) {
      return std::string(error.what()).find("every-domain distance >= 0") != std::string::npos;
    }
    return false;
  };
  testing::LimitDistanceOptions options;
  EXPECT_FALSE(refused(options));
  options.everyDomainBeyond = 0;
  EXPECT_FALSE(refused(options));
  for (double beyond : {-1.0, std::nan("")}) {
    options.everyDomainBeyond = beyond;
    EXPECT_TRUE(refused(options)) << beyond;
  }
  options = {};
  options.triangleSamples = 1;
  EXPECT_TRUE(refused(options));
  options = {};
  options.spatialSeeds = 17;
  EXPECT_TRUE(refused(options));
}

TEST(LimitDistanceTest, UniformTessellationIsWatertight) {
  for (const char* name : {"catmark_cube", "catmark_nonquads", "catmark_bishop"}) {
    const LimitSurface surface(shape(name));
    const Far::TopologyLevel& level = surface.baseLevel();
    int boundaryEdges = 0;
    for (int e = 0; e < level.GetNumEdges(); ++e) {
      boundaryEdges += level.GetEdgeFaces(e).size() == 1 ? 1 : 0;
    }
    for (int rate : {1, 3, 4}) {
      const UniformTessellation mesh = tessellateUniform(surface, rate);
      std::map<std::pair<uint32_t, uint32_t>, int> directedEdges;
      for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const uint32_t* corner = &mesh.indices[3 * t];
        for (int k = 0; k < 3; ++k) ++directedEdges[{corner[k], corner[(k + 1) % 3]}];
      }
      // Consistently oriented and closed except along the control mesh's boundary, whose edges
      // are split into `rate` mesh edges each.
      int unpaired = 0;
      for (const auto& [edge, count] : directedEdges) {
        EXPECT_EQ(count, 1) << name << " rate " << rate;
        unpaired += directedEdges.count({edge.second, edge.first}) == 0;
      }
      EXPECT_EQ(unpaired, boundaryEdges * rate) << name << " rate " << rate;
    }
  }
}

TEST(LimitDistanceTest, TriangleCornerParametersEvaluateToTheirVertices) {
  // N-gon triangles straddle sub-faces: corners unfolded into the triangle's sub-face must map
  // back (LimitSurface::continueDomain) to where their vertex was evaluated.
  for (const char* name : {"catmark_nonquads", "catmark_bishop"}) {
    const LimitSurface surface(shape(name));
    for (int rate : {1, 2, 3, 4}) {
      const UniformTessellation mesh = tessellateUniform(surface, rate);
      double worst = 0;
      for (size_t t = 0; t < mesh.triangleCount(); ++t) {
        const int domain = surface.domainOf(mesh.triangleFace[t], mesh.triangleSubFace[t]);
        for (int c = 0; c < 3; ++c) {
          double u = mesh.cornerUv[6 * t + 2 * c], v = mesh.cornerUv[6 * t + 2 * c + 1];
          const int continued = surface.continueDomain(domain, u, v);
          Vec3d x;
          surface.evaluate(continued, u, v, x);
          worst = std::max(worst, length(x - Vec3d(mesh.positions[mesh.indices[3 * t + c]])));
        }
      }
      EXPECT_LT(worst, 1e-6 * surface.diagonal()) << name << " rate " << rate;
    }
  }
}

// The nearest point to p of face f's limit surface: the best of a 16×16 grid on each of its
// domains, refined by Gauss-Newton.
double bruteForceDistanceToFace(const LimitSurface& surface, int face, const Vec3d& p) {
  double best = 1e300;
  for (int d = 0; d < surface.domainCount(); ++d) {
    if (surface.domains()[d].face != face) continue;
    testing::LimitPoint start;
    for (int y = 0; y <= 16; ++y) {
      for (int x = 0; x <= 16; ++x) {
        Vec3d q;
        surface.evaluate(d, x / 16.0, y / 16.0, q);
        if (length(q - p) < start.distance) start = {d, x / 16.0, y / 16.0, q, length(q - p)};
      }
    }
    best = std::min({best, start.distance,
                     testing::projectInDomain(surface, p, d, start.u, start.v, 1e-12).distance});
  }
  return best;
}

TEST(LimitDistanceTest, NgonTrianglesAcrossSubFacesAreProjectedIntoTheRightSubFace) {
  // At rate 3 Bfr's n-gon triangles straddle sub-faces: their corners are unfolded past a spoke
  // and the samples' parametric seeds must continue into the neighbouring sub-face. With one
  // spatial seed, each such triangle measured alone must match a brute-force search of its face.
  const LimitSurface surface(shape("catmark_nonquads"));
  const UniformTessellation mesh = tessellateUniform(surface, 3);
  testing::LimitDistanceOptions options;
  options.spatialSeeds = 1;
  int straddling = 0;
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    const double* uv = &mesh.cornerUv[6 * t];
    if (*std::max_element(uv, uv + 6) <= 1.0) continue;
    ++straddling;
    testing::TriangleMeshView alone = mesh.view();
    alone.indices = alone.indices.subspan(3 * t, 3);
    alone.triangleFace = alone.triangleFace.subspan(t, 1);
    alone.triangleSubFace = alone.triangleSubFace.subspan(t, 1);
    alone.cornerUv = alone.cornerUv.subspan(6 * t, 6);
    const double measured = measureLimitDistance(surface, alone, options).meshToLimit;
    double expected = 0;
    for (int i = 0; i <= 4; ++i) {
      for (int j = 0; i + j <= 4; ++j) {
        if (i == 4 || j == 4 || i + j == 0) continue;  // K = 4, corners excluded
        const double b[3] = {i / 4.0, j / 4.0, (4 - i - j) / 4.0};
        Vec3d p;
        for (int k = 0; k < 3; ++k) p += Vec3d(mesh.positions[mesh.indices[3 * t + k]]) * b[k];
        expected = std::max(expected, bruteForceDistanceToFace(surface, mesh.triangleFace[t], p));
      }
    }
    EXPECT_LE(measured, expected + 1e-9 * surface.diagonal()) << "triangle " << t;
  }
  EXPECT_GT(straddling, 20);
}

TEST(LimitDistanceTest, DerivativesMatchFiniteDifferencesOnBothBackends) {
  const ControlMesh mesh = shape("catmark_nonquads");  // n-gon sub-faces scale derivatives
  for (LimitSurface::Backend backend : {LimitSurface::Backend::kBfr, LimitSurface::Backend::kFar}) {
    const LimitSurface surface(mesh, backend);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> inside(0.05, 0.95);
    for (int i = 0; i < 200; ++i) {
      const int d = int(random() % surface.domainCount());
      const double u = inside(random), v = inside(random), h = 1e-6;
      Vec3d p, du, dv, a, b, c, e;
      surface.evaluate(d, u, v, p, &du, &dv);
      surface.evaluate(d, u + h, v, a), surface.evaluate(d, u - h, v, b);
      surface.evaluate(d, u, v + h, c), surface.evaluate(d, u, v - h, e);
      EXPECT_LT(length((a - b) * (0.5 / h) - du), 1e-5 * length(du)) << "domain " << d;
      EXPECT_LT(length((c - e) * (0.5 / h) - dv), 1e-5 * length(dv)) << "domain " << d;
    }
  }
}

TEST(LimitDistanceTest, InteriorValence2MeshesAreMeasuredAgainstFar) {
  const ControlMesh mesh = shape("catmark_val2_interior");
  const LimitSurface surface(mesh);
  EXPECT_EQ(surface.backend(), LimitSurface::Backend::kFar);
  const LimitDistanceReport at8 =
      measureLimitDistance(surface, tessellateUniform(surface, 8).view());
  const LimitDistanceReport at16 =
      measureLimitDistance(surface, tessellateUniform(surface, 16).view());
  // Slower than 1/R² (2.4x from 8 to 16: the surface folds tightly next to the valence-2 vertex).
  EXPECT_LT(at16.twoSidedRelative(), 1e-3);
  EXPECT_GT(at8.twoSided() / at16.twoSided(), 2.0);
}

TEST(LimitDistanceTest, BvhNearestPointMatchesBruteForce) {
  std::mt19937 random(3);
  std::uniform_real_distribution<float> coordinate(-1, 1);
  std::vector<Vec3> positions(300);
  for (Vec3& p : positions) p = Vec3(coordinate(random), coordinate(random), coordinate(random));
  std::vector<uint32_t> indices;
  for (int t = 0; t < 500; ++t) {
    for (int k = 0; k < 3; ++k) indices.push_back(uint32_t(random() % positions.size()));
  }
  const testing::TriangleBvh bvh(positions, indices);
  for (int q = 0; q < 300; ++q) {
    const Vec3d p(2 * coordinate(random), 2 * coordinate(random), 2 * coordinate(random));
    double best = 1e300;
    for (size_t t = 0; t < indices.size() / 3; ++t) {
      const Vec3d x = testing::closestPointOnTriangle(p, Vec3d(positions[indices[3 * t]]),
                                                      Vec3d(positions[indices[3 * t + 1]]),
                                                      Vec3d(positions[indices[3 * t + 2]]));
      best = std::min(best, length(x - p));
    }
    EXPECT_DOUBLE_EQ(bvh.nearest(p).distance, best);
  }
}

TEST(LimitDistanceTest, ClosestPointOnTriangleIsNeverFartherThanAnySamplePoint) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> coordinate(-1, 1), weight(0, 1);
  for (int i = 0; i < 2000; ++i) {
    const Vec3d a(coordinate(random), coordinate(random), coordinate(random));
    const Vec3d b(coordinate(random), coordinate(random), coordinate(random));
    const Vec3d c(coordinate(random), coordinate(random), coordinate(random));
    const Vec3d p(2 * coordinate(random), 2 * coordinate(random), 2 * coordinate(random));
    const double closest = length(testing::closestPointOnTriangle(p, a, b, c) - p);
    double s = weight(random), t = weight(random);
    if (s + t > 1) s = 1 - s, t = 1 - t;
    EXPECT_LE(closest, length(a + (b - a) * s + (c - a) * t - p) + 1e-12);
  }
}

}  // namespace
}  // namespace tessera
