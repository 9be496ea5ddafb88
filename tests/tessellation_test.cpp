// Error-bounded, watertight tessellation against OpenSubdiv's exact limit surface.
//
// Distance on the adaptive path: measured two-sided by projection onto the limit surface
// (reference/limit_distance.h), as the bound it proves is geometric.
// On the paper's single-phase path: every triangle lies in one plan piece, so for sample points q
// of a triangle the mesh point L(q) and the surface point x(q) correspond; max ‖L(q) − x(q)‖
// bounds both one-sided distances (mesh → surface, and surface → mesh, since the triangles tile
// each piece's domain exactly). x comes from Bfr (Far's patch table for valence-2 shapes), exact
// for what lies at Far level 10 or above.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <map>
#include <set>
#include <optional>
#include <random>

#include "core/base/error.h"
#include "core/output/glb_writer.h"
#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "core/pipeline/tessellate.h"
#include "reference/bfr_reference.h"
#include "reference/far_patch_reference.h"
#include "tests/support/glb_reader.h"
#include "tests/support/gltf_validator.h"
#include "reference/limit_distance.h"
#include "tests/support/mesh_equality.h"
#include "reference/limit_surface.h"
#include "reference/models.h"

namespace tessera {
namespace {

constexpr int kBfrExactLevel = 10;
constexpr size_t kMaxSampledTriangles = 60000;

double diagonalOf(const PatchSet& set) { return length(Vec3d(set.boundsMax) - Vec3d(set.boundsMin)); }

struct Measured {
  double worst = 0;
  size_t triangles = 0, sampled = 0;
};

// The plan piece and corner coordinates of a triangle on the single-phase path.
struct TriangleDomain {
  PatchDomain domain;
  double st[6];
  int depth = 0;  // how far below the base face the piece lies
};

TriangleDomain domainOf(const TessellationResult& result, size_t tri) {
  const TriangleMesh& mesh = result.mesh;
  TriangleDomain d;
  std::copy(&mesh.triangleST[6 * tri], &mesh.triangleST[6 * tri] + 6, d.st);
  const BezierPiece& piece = result.plan.pieces[mesh.trianglePiece[tri]];
  d.domain = piece.domain;
  d.depth = piece.depth;
  return d;
}

template <typename Reference>
Measured measure(const TessellationResult& result, Reference& reference) {
  static const double kBarycentric[7][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5, 0.5, 0},
                                            {0, 0.5, 0.5}, {0.5, 0, 0.5}, {1 / 3.0, 1 / 3.0, 1 / 3.0}};
  const TriangleMesh& mesh = result.mesh;
  Measured m;
  m.triangles = mesh.triangleCount();
  const size_t stride = std::max<size_t>(1, m.triangles / kMaxSampledTriangles);
  for (size_t tri = 0; tri < m.triangles; tri += stride) {
    const TriangleDomain d = domainOf(result, tri);
    if (d.depth > kBfrExactLevel) continue;
    for (const auto& b : kBarycentric) {
      double s = b[0] * d.st[0] + b[1] * d.st[2] + b[2] * d.st[4], t = b[0] * d.st[1] + b[1] * d.st[3] + b[2] * d.st[5];
      Vec3d onMesh;
      for (int k = 0; k < 3; ++k) onMesh += Vec3d(mesh.positions[mesh.indices[3 * tri + k]]) * b[k];
      Vec3d exact;
      EXPECT_TRUE(reference.evaluate(d.domain, s, t, exact));
      m.worst = std::max(m.worst, length(onMesh - exact));
    }
    ++m.sampled;
  }
  return m;
}

TessellationResult tessellateAt(const ControlMesh& mesh, const PatchSet& set, double relative,
                                double eta = 0.5) {
  TessellationOptions options;
  options.accuracy = Accuracy::relative(relative);
  options.eta = eta;
  options.recordParameters = true;
  return tessellate(set, mesh, options);
}

// Undirected edge use counts; a closed surface uses every edge twice, in opposite directions.
// On an input edge with more than two faces, or two running the same way, the output edges along
// it must be used by as many triangles, each way, as the input edge is by faces (the copies of a
// point are one point: the edge stays shared, not cracked into one boundary per face).
struct EdgeCheck {
  size_t boundaryEdges = 0, nonManifoldEdges = 0, misorientedEdges = 0, boundaryOffInputBoundary = 0;
  size_t onNonManifoldInput = 0, nonManifoldUseMismatch = 0;
};

// Faces on each input edge (lo, hi) running lo → hi and hi → lo, holes left out.
struct EdgeUses {
  int forward = 0, backward = 0;
  int folded = 0;  // faces that run along the edge both ways (each counted in both directions)
  bool manifold() const { return forward + backward <= 1 || (forward == 1 && backward == 1); }
};

// The copies that give each side of a crease (or a fold) its own normal are one point of the
// surface; they must repeat their point's position bit for bit.
std::vector<uint32_t> pointsOf(const TriangleMesh& mesh) {
  std::vector<uint32_t> point(mesh.positions.size());
  for (uint32_t v = 0; v < mesh.positions.size(); ++v) {
    point[v] = mesh.vertexPoint.empty() ? v : mesh.vertexPoint[v];
    const Vec3 &a = mesh.positions[v], &b = mesh.positions[point[v]];
    EXPECT_TRUE(a.x == b.x && a.y == b.y && a.z == b.z) << "vertex " << v << " moved off its point";
  }
  return point;
}

// A face that repeats a vertex consecutively has a side of no length: every point on that
// degenerate line (a, a) is the surface's point at vertex a, and is one point with it here
// (it must lie there: within a few float roundings of the vertex). Triangles that
// collapse with it have no area and leave the edge count.
void collapseDegenerateLines(const TriangleMesh& mesh, const FaceTopology& faces, std::vector<uint32_t>& point) {
  std::vector<DomainKey> keys;
  std::map<int, uint32_t> node;  // per vertex with a degenerate line: its point (a vertex's, if any)
  for (uint32_t v = 0; v < mesh.positions.size(); ++v) {
    keys.push_back(pointKey(faces, mesh.vertexFace[v], mesh.vertexSubFace[v], mesh.vertexUv[2 * v], mesh.vertexUv[2 * v + 1]));
    if (keys[v].kind == DomainKey::kEdge && keys[v].a == keys[v].b) node.try_emplace(keys[v].a, point[v]);
  }
  for (uint32_t v = 0; v < mesh.positions.size(); ++v) {
    if (keys[v].kind == DomainKey::kVertex && node.count(keys[v].a)) node[keys[v].a] = point[v];
  }
  double extent = 0;
  for (const Vec3& p : mesh.positions) extent = std::max({extent, double(std::abs(p.x)), double(std::abs(p.y)), double(std::abs(p.z))});
  for (uint32_t v = 0; v < mesh.positions.size(); ++v) {
    const DomainKey& key = keys[v];
    if (key.kind != DomainKey::kVertex && !(key.kind == DomainKey::kEdge && key.a == key.b)) continue;
    const auto found = node.find(key.a);
    if (found == node.end()) continue;
    EXPECT_LE(length(Vec3d(mesh.positions[v]) - Vec3d(mesh.positions[found->second])), 4 * FLT_EPSILON * extent)
        << "vertex " << v;
    point[v] = found->second;
  }
}

EdgeCheck checkEdges(const TriangleMesh& mesh, const ControlMesh& control) {
  FaceTopology faces(control.faceSizes, control.faceVertices);
  std::vector<uint32_t> point = pointsOf(mesh);
  collapseDegenerateLines(mesh, faces, point);
  // Faces without area are left out like holes: a face with fewer than three distinct vertices
  // (OpenSubdiv's catmark_nonman_edges has "81 81 81 82") has a curve or a point for a surface,
  // where no crack can open.
  std::vector<bool> hole = testing::facesWithoutSurface(control);
  for (int f = 0; f < control.faceCount(); ++f) {
    std::set<int> distinct;
    for (int k = 0; k < faces.size(f); ++k) distinct.insert(faces.corner(f, k));
    if (distinct.size() < 3) hole[f] = true;
  }
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (size_t i = 0; i < mesh.indices.size(); i += 3) {
    const uint32_t p[3] = {point[mesh.indices[i]], point[mesh.indices[i + 1]], point[mesh.indices[i + 2]]};
    // (The single-phase path records no triangle's face; it meets no face without area here.)
    const bool flat = !mesh.triangleFace.empty() && hole[mesh.triangleFace[i / 3]];
    if (p[0] == p[1] || p[1] == p[2] || p[2] == p[0] || flat) continue;
    for (int k = 0; k < 3; ++k) ++directed[{p[k], p[(k + 1) % 3]}];
  }
  // Base edges with one face that is not a hole (the input's boundary, holes included).
  std::map<std::pair<int, int>, int> baseEdges;
  std::map<std::pair<int, int>, EdgeUses> uses;
  for (int f = 0; f < control.faceCount(); ++f) {
    if (hole[f]) continue;
    for (int k = 0; k < faces.size(f); ++k) {
      int a = faces.corner(f, k), b = faces.corner(f, k + 1);
      ++baseEdges[{std::min(a, b), std::max(a, b)}];
      EdgeUses& use = uses[{std::min(a, b), std::max(a, b)}];
      ++(a < b ? use.forward : use.backward);
      for (int j = k + 1; j < faces.size(f); ++j) {
        const int c = faces.corner(f, j), d = faces.corner(f, j + 1);
        use.folded += std::min(c, d) == std::min(a, b) && std::max(c, d) == std::max(a, b) && c != d;
      }
    }
  }
  auto keyOf = [&](uint32_t v) {
    return pointKey(faces, mesh.vertexFace[v], mesh.vertexSubFace[v], mesh.vertexUv[2 * v], mesh.vertexUv[2 * v + 1]);
  };
  auto onInputBoundary = [&](uint32_t v) {
    DomainKey key = keyOf(v);
    if (key.kind == DomainKey::kEdge) return baseEdges[{key.a, key.b}] == 1;
    return key.kind == DomainKey::kVertex;  // corners: checked through their edges' other end
  };
  auto onBoundaryOf = [&](int f, const DomainKey& key) {
    for (int k = 0; k < faces.size(f); ++k) {
      const int a = faces.corner(f, k), b = faces.corner(f, k + 1);
      if (key.kind == DomainKey::kVertex && a == key.a) return true;
      if (key.kind == DomainKey::kEdge && std::min(a, b) == key.a && std::max(a, b) == key.b) return true;
    }
    return false;
  };
  // Where the input is not a manifold, an output edge p → q may be shared by more than two
  // triangles: its uses p → q and q → p. Along a non-manifold input edge, as many each way as
  // the input edge has faces that way; across faces that share both its ends (the sides of a
  // two-sided face), as many each way, at most one per face (-count: "at most").
  auto nonManifoldInput = [&](uint32_t p, uint32_t q, int& along, int& back, int& folded) {
    DomainKey a = keyOf(p), b = keyOf(q);
    const auto onLine = [](const DomainKey& k) { return k.kind == DomainKey::kVertex || k.kind == DomainKey::kEdge; };
    if (b.kind == DomainKey::kInterior && onLine(a)) std::swap(a, b);  // the answer is symmetric
    if (a.kind == DomainKey::kInterior && onLine(b)) {
      // A face that runs along one edge twice (it repeats a vertex) folds onto that edge: its
      // points near both sides meet the edge's points from both, at most once per side each way.
      int sides = 0;
      for (int k = 0; k < faces.size(a.a); ++k) {
        const int p = faces.corner(a.a, k), q = faces.corner(a.a, k + 1);
        sides += b.kind == DomainKey::kEdge ? std::min(p, q) == b.a && std::max(p, q) == b.b : p == b.a;
      }
      along = back = -sides;
      return sides > 1;
    }
    if (!onLine(a) || !onLine(b)) return false;
    const auto endOf = [](const DomainKey& k, const std::pair<int, int>& e) { return k.a == e.first ? 0.0 : 1.0; };
    std::pair<int, int> edge{-1, -1};
    if (a.kind == DomainKey::kEdge) edge = {a.a, a.b};
    if (b.kind == DomainKey::kEdge) edge = {b.a, b.b};
    if (a.kind == DomainKey::kVertex && b.kind == DomainKey::kVertex) edge = {std::min(a.a, b.a), std::max(a.a, b.a)};
    const auto lies = [&](const DomainKey& k) {
      return k.kind == DomainKey::kEdge ? k.a == edge.first && k.b == edge.second
                                        : k.a == edge.first || k.a == edge.second;
    };
    const auto found = uses.find(edge);
    if (found != uses.end() && lies(a) && lies(b)) {
      if (found->second.manifold()) return false;
      const double ta = a.kind == DomainKey::kEdge ? a.x : endOf(a, edge);
      const double tb = b.kind == DomainKey::kEdge ? b.x : endOf(b, edge);
      along = ta < tb ? found->second.forward : found->second.backward;
      back = ta < tb ? found->second.backward : found->second.forward;
      folded = found->second.folded;
      return true;
    }
    int shared = 0;
    for (int f = 0; f < control.faceCount(); ++f) shared += !hole[f] && onBoundaryOf(f, a) && onBoundaryOf(f, b);
    along = back = -shared;  // at most
    return shared > 1;
  };
  EdgeCheck check;
  for (const auto& [edge, count] : directed) {
    const int reverse = directed.count({edge.second, edge.first}) ? directed.at({edge.second, edge.first}) : 0;
    int along = 0, back = 0, folded = 0;
    if (nonManifoldInput(edge.first, edge.second, along, back, folded)) {
      ++check.onNonManifoldInput;
      // A face folded along the edge may meet it from both sides or, where its corner tile
      // collapses onto the edge, from neither: one use each way, or none.
      const bool expected = along < 0 ? count == reverse && count <= -along
                                      : count - reverse == along - back && count <= along && reverse <= back &&
                                            count >= along - folded && reverse >= back - folded;
      if (!expected) ++check.nonManifoldUseMismatch;
      continue;
    }
    if (count > 1) ++check.misorientedEdges;
    if (count + reverse > 2) ++check.nonManifoldEdges;
    if (reverse == 0) {
      ++check.boundaryEdges;
      if (!onInputBoundary(edge.first) || !onInputBoundary(edge.second)) ++check.boundaryOffInputBoundary;
    }
  }
  return check;
}

bool hasBoundary(const ControlMesh& mesh) {
  std::map<std::pair<int, int>, int> edges;
  FaceTopology faces(mesh.faceSizes, mesh.faceVertices);
  for (int f = 0; f < mesh.faceCount(); ++f) {
    for (int k = 0; k < faces.size(f); ++k) {
      int a = faces.corner(f, k), b = faces.corner(f, k + 1);
      ++edges[{std::min(a, b), std::max(a, b)}];
    }
  }
  for (const auto& [edge, count] : edges) {
    if (count == 1) return true;
  }
  const std::vector<bool> hole = testing::facesWithoutSurface(mesh);
  return std::find(hole.begin(), hole.end(), true) != hole.end();
}

// The adaptive path (η > 0) bounds the geometric distance (docs/ADAPTIVE.md §3a: a tile may be
// compared with the surface through a reparameterization), so its mesh is measured two-sided by
// projection (reference/limit_distance.h); η = 0 keeps the paper's parametric bound, measured
// at the same parameters.
template <typename Reference>
void expectWithinToleranceAndWatertight(const std::string& path, const ControlMesh& mesh,
                                        Reference& reference, double eta) {
  constexpr double kReferenceAccuracy = testing::LimitSurface::kRelativeAccuracy;
  PatchSet set = buildPatchSet(mesh);
  const double diagonal = diagonalOf(set);
  std::optional<testing::LimitSurface> surface;
  if (eta > 0) surface.emplace(mesh);
  double previous = INFINITY;
  for (double relative : {1e-2, 1e-3, 1e-4}) {
    SCOPED_TRACE(testing::baseName(path) + " at " + std::to_string(relative) + ", eta " +
                 std::to_string(eta));
    TessellationResult result = tessellateAt(mesh, set, relative, eta);
    const double epsilon = relative * diagonal;
    double worst = 0;
    if (surface) {
      const testing::LimitDistanceReport report = measureLimitDistance(*surface, testing::viewOf(result.mesh));
      worst = report.twoSided();
      EXPECT_LE(worst, epsilon + kReferenceAccuracy * diagonal)
          << "at face " << report.twoSidedAt().face << " (" << report.twoSidedAt().u << ", " << report.twoSidedAt().v << ")";
    } else {
      const Measured m = measure(result, reference);
      worst = m.worst;
      EXPECT_LE(worst, epsilon) << m.sampled << " of " << m.triangles << " triangles sampled";
    }
    EXPECT_LE(result.summary.guaranteedBound, epsilon);
    EXPECT_LE(worst, previous + kReferenceAccuracy * diagonal) << "lowering the tolerance raised the measured error";
    previous = worst;
    EdgeCheck edges = checkEdges(result.mesh, mesh);
    EXPECT_EQ(edges.nonManifoldEdges, 0u);
    EXPECT_EQ(edges.misorientedEdges, 0u);
    EXPECT_EQ(edges.nonManifoldUseMismatch, 0u) << "of " << edges.onNonManifoldInput << " on non-manifold input edges";
    if (hasBoundary(mesh)) {
      EXPECT_EQ(edges.boundaryOffInputBoundary, 0u);
    } else {
      EXPECT_EQ(edges.boundaryEdges, 0u);
    }
    std::printf("%-28s eps %.0e: %8zu triangles, worst %.3g (%.2f of eps)\n", testing::baseName(path).c_str(),
                relative, result.mesh.triangleCount(), worst, worst / epsilon);
  }
}

void expectModel(const std::string& path, double eta = 0.5) {
  ControlMesh mesh = readObjFile(path);
  if (testing::baseName(path).find("val2") != std::string::npos) {
    testing::FarPatchReference reference(mesh);
    expectWithinToleranceAndWatertight(path, mesh, reference, eta);
  } else {
    testing::BfrReference reference(mesh);
    expectWithinToleranceAndWatertight(path, mesh, reference, eta);
  }
}

TEST(Tessellation, BenchmarkCharactersStayWithinToleranceAndAreWatertight) {
  for (const std::string& path : testing::benchmarkCharacters()) expectModel(path);
}

TEST(Tessellation, OpenSubdivShapesStayWithinToleranceAndAreWatertight) {
  for (const std::string& path : testing::openSubdivShapes()) {
    ControlMesh mesh;
    try {
      mesh = readObjFile(path);
      buildPatchSet(mesh);
    } catch (const TesseraError&) {
      continue;  // refused shapes are covered by PatchSet.OpenSubdivShapes...
    }
    expectModel(path);
  }
}

// Holes anywhere: next to extraordinary vertices, boundaries, corners, semi-sharp creases,
// valence-2 vertices and non-manifold edges, in random layouts (a fixed seed per layout). Far
// leaves a sparse level without a hole's faces, and rings beside holes once lost their lattice
// or met a semi-sharp edge there (most of these shapes were refused in most random layouts);
// within ε of Bfr's surface with the same holes, and crack-free, the holes' edges being the only
// new boundary.
TEST(Tessellation, RandomHoleLayoutsStayWithinToleranceAndAreWatertight) {
  const std::string shapes = testing::modelsDir() + "/opensubdiv-shapes/";
  for (const char* name : {"catmark_pole8", "catmark_xord_interior", "catmark_quadstrips", "catmark_fan",
                           "catmark_cube_creases0", "catmark_cubes_semisharp", "catmark_val2_interior"}) {
    const ControlMesh original = readObjFile(shapes + name + ".obj");
    for (uint32_t seed : {1u, 2u, 3u}) {
      std::mt19937 random(seed);
      ControlMesh mesh = original;
      std::set<int> holes;
      const int count = 1 + int(random() % uint32_t(std::max(1, mesh.faceCount() / 3)));
      for (int i = 0; i < count; ++i) holes.insert(int(random() % uint32_t(mesh.faceCount())));
      mesh.holes.assign(holes.begin(), holes.end());
      const std::string label = std::string(name) + " with holes, seed " + std::to_string(seed);
      if (label.find("val2") != std::string::npos) {
        testing::FarPatchReference reference(mesh);
        expectWithinToleranceAndWatertight(label, mesh, reference, 0.5);
      } else {
        testing::BfrReference reference(mesh);
        expectWithinToleranceAndWatertight(label, mesh, reference, 0.5);
      }
    }
  }
}

// Chaikin creases, smooth triangles and VTX_BOUNDARY_NONE change the limit surface by more than
// the tolerance (the default rules' mesh is measured far from it), and the mesh made under the
// file's rules is within it: the rules reach the surface Tessera tessellates, not only the reader.
TEST(Tessellation, CreaseTriangleAndBoundaryRulesShapeTheSurface) {
  constexpr double kRelative = 1e-3;
  for (const char* name : {"catmark_chaikin2", "catmark_smoothtris1", "catmark_edgenone"}) {
    SCOPED_TRACE(name);
    const ControlMesh mesh = readObjFile(testing::modelsDir() + "/opensubdiv-shapes/" + name + ".obj");
    ControlMesh byDefault = mesh;
    byDefault.rules = SubdivisionRules{};
    ASSERT_NE(mesh.rules, byDefault.rules);
    const testing::LimitSurface surface(mesh);
    const PatchSet set = buildPatchSet(mesh);
    const double epsilon = kRelative * diagonalOf(set);
    const double followed =
        measureLimitDistance(surface, testing::viewOf(tessellateAt(mesh, set, kRelative, 0.5).mesh)).twoSided();
    const double ignored =
        measureLimitDistance(surface, testing::viewOf(tessellateAt(byDefault, buildPatchSet(byDefault), kRelative, 0.5).mesh))
            .twoSided();
    std::printf("%-20s rules followed %.3g, default rules %.3g (eps %.3g)\n", name, followed, ignored, epsilon);
    EXPECT_LE(followed, epsilon * (1 + testing::LimitSurface::kRelativeAccuracy / kRelative));
    EXPECT_GT(ignored, 2 * epsilon);
  }
}

// η = 0, the paper's single-phase baseline: the depth alone must carry the innermost quads, now
// triangle pairs, within ε; smooth, crease, corner, boundary and dart rings.
TEST(Tessellation, SinglePhaseStaysWithinToleranceAndIsWatertight) {
  const std::string shapes = testing::modelsDir() + "/opensubdiv-shapes/";
  for (const std::string& path :
       {testing::modelsDir() + "/bigguy.obj", shapes + "catmark_cube_creases2.obj",
        shapes + "catmark_cube_corner4.obj", shapes + "catmark_edgecorner.obj",
        shapes + "catmark_dart_edgeonly.obj", shapes + "catmark_pole64.obj"}) {
    expectModel(path, 0.0);
  }
}

TEST(Tessellation, SinglePhaseMakesInnermostQuadsTrianglePairs) {
  ControlMesh mesh = readObjFile(testing::modelsDir() + "/bigguy.obj");
  PatchSet set = buildPatchSet(mesh);
  TessellationResult result = tessellateAt(mesh, set, 1e-3, 0.0);
  size_t innermost = 0, notAPair = 0;
  for (const BezierPiece& piece : result.plan.pieces) {
    if (piece.kind != PieceKind::kInnermost) continue;
    ++innermost;
    notAPair += piece.level != 1;
  }
  EXPECT_GT(innermost, 0u);
  EXPECT_EQ(notAPair, 0u);
}

// The tessellator works on all cores; its mesh must not depend on how many there are.
TEST(Tessellation, TheMeshIsTheSameWhateverTheThreadCount) {
  const std::string shapes = testing::modelsDir() + "/opensubdiv-shapes/";
  for (const std::string& path :
       {testing::modelsDir() + "/bigguy.obj", testing::modelsDir() + "/car.obj",
        shapes + "catmark_nonquads.obj", shapes + "catmark_hole_test1.obj"}) {
    SCOPED_TRACE(testing::baseName(path));
    ControlMesh mesh = readObjFile(path);
    PatchSet set = buildPatchSet(mesh);
    TessellationResult parallel = tessellateAt(mesh, set, 1e-3);
    TessellationResult serial;
    tbb::task_arena oneThread(1);
    oneThread.execute([&] { serial = tessellateAt(mesh, set, 1e-3); });
    EXPECT_EQ(testing::meshDifference(parallel.mesh, serial.mesh), "");
  }
}

TEST(Tessellation, WritesGlbThatKhronosValidatorAccepts) {
  for (const char* name : {"bigguy", "opensubdiv-shapes/catmark_edgecorner"}) {
    ControlMesh mesh = readObjFile(testing::modelsDir() + "/" + name + ".obj");
    PatchSet set = buildPatchSet(mesh);
    TessellationResult result = tessellateAt(mesh, set, 1e-3);
    std::vector<uint8_t> glb = writeGlb(result.mesh, {.description = {.sourceName = name}});
    TriangleMesh back = testing::readGlb(glb);
    ASSERT_EQ(back.positions.size(), result.mesh.positions.size());
    ASSERT_EQ(back.indices, result.mesh.indices);
    for (size_t v = 0; v < back.positions.size(); ++v) {
      ASSERT_EQ(back.positions[v].x, result.mesh.positions[v].x);
      ASSERT_EQ(back.normals[v].z, result.mesh.normals[v].z);
    }
    testing::ValidatorReport validation = testing::validateGlb(glb, testing::baseName(name));
    ASSERT_TRUE(validation.ran) << "glTF-Validator did not run (npm install in tests/gltf?): "
                                << validation.report;
    EXPECT_TRUE(validation.clean()) << validation.report;
  }
}

TEST(Tessellation, RefusesBadOptionsWithClearErrors) {
  ControlMesh mesh = readObjFile(testing::modelsDir() + "/bigguy.obj");
  PatchSet set = buildPatchSet(mesh);
  auto expectError = [&](TessellationOptions options, ErrorKind kind, const std::string& mentions) {
    try {
      tessellate(set, mesh, options);
      ADD_FAILURE() << "accepted; expected an error mentioning " << mentions;
    } catch (const TesseraError& e) {
      EXPECT_EQ(e.kind(), kind) << e.what();
      EXPECT_NE(std::string(e.what()).find(mentions), std::string::npos) << e.what();
    }
  };
  TessellationOptions o;
  o.accuracy = Accuracy::absolute(0);
  expectError(o, ErrorKind::kInvalidInput, "tolerance");
  o.accuracy = Accuracy::absolute(-1);
  expectError(o, ErrorKind::kInvalidInput, "tolerance");
  o.accuracy = Accuracy::absolute(NAN);
  expectError(o, ErrorKind::kInvalidInput, "tolerance");
  o.accuracy = Accuracy::relative(1);
  expectError(o, ErrorKind::kInvalidInput, "below 1");
  o.accuracy = Accuracy::uniformLevel(0);
  expectError(o, ErrorKind::kInvalidInput, "uniform level");
  o = {};
  o.eta = 1.5;
  expectError(o, ErrorKind::kInvalidInput, "eta");
  o.eta = -0.1;
  expectError(o, ErrorKind::kInvalidInput, "eta");
  o = {};
  o.accuracy = Accuracy::relative(1e-6);
  o.maxTriangles = 100000;
  expectError(o, ErrorKind::kLimitExceeded, "budget");
  o = {};
  o.accuracy = Accuracy::pixel(0.5);
  o.camera = Camera{{0, 0, 10}, {0, 0, 10}};
  expectError(o, ErrorKind::kInvalidInput, "eye and target must be distinct");
  o.camera = Camera{{0, 0, 10}, {0, 0, 0}, {0, 0, 1}};
  expectError(o, ErrorKind::kInvalidInput, "camera.up: must not be parallel");
  o.camera = Camera{{0, 0, 10}, {0, 0, 0}, {0, 1e-7, 1}};  // a sine of 1e-7: no roll in float
  expectError(o, ErrorKind::kInvalidInput, "camera.up: must not be parallel");
  o.camera = Camera{{0, 0, 10}, {0, 0, 0}, {0, 1e-5, 1}};
  o.accuracy = Accuracy::pixel(4000);
  expectError(o, ErrorKind::kInvalidInput, "larger than the 1920x1080 viewport");
  o.accuracy = Accuracy::absolute(1e-3);
  expectError(o, ErrorKind::kInvalidInput, "a camera was given without a pixel accuracy");
  o.camera.reset();
  o.accuracy = Accuracy::pixel(0.5);
  expectError(o, ErrorKind::kInvalidInput, "needs the camera");
}

TEST(Tessellation, PixelAccurateToleranceShrinksWithDistance) {
  ControlMesh mesh = readObjFile(testing::modelsDir() + "/bigguy.obj");
  PatchSet set = buildPatchSet(mesh);
  auto trianglesFrom = [&](double distance) {
    TessellationOptions o;
    Vec3d center = (Vec3d(set.boundsMin) + Vec3d(set.boundsMax)) * 0.5;
    o.accuracy = Accuracy::pixel(0.5);
    o.camera = Camera{center + Vec3d(0, 0, distance), center, {0, 1, 0}, 45, 512, 512};
    return tessellate(set, mesh, o).summary.triangles;
  };
  EXPECT_GT(trianglesFrom(20), trianglesFrom(80));
}

}  // namespace
}  // namespace tessera
