// tessera-crease-stand-in: how far a mesh's limit surface lies from the one with its semi-sharp
// creases made infinitely sharp, measured and bounded (bench/COLD-RESULTS.md, "The infinitely sharp
// crease as a stand-in"). The stand-in needs no isolation of the creases; serving a request from
// it needs a bound on the difference, and this checks the one proposed there:
//
//  - measured: both meshes refined uniformly to level J ≥ ⌈s⌉ by Far (the same topology, so the
//    same vertex numbering) and every level-J vertex's limit position compared (a lower estimate
//    of the sup of the difference);
//  - bounded, for each level j ≤ min(J, L), L the least ⌊s⌋ of the creases made sharp: up to L
//    levels both rule sets make the same points (checked here), every Catmull-Clark rule is a
//    convex combination, and the children's 1-rings of a face are made from points of its own, so
//    over a level-j face both limit surfaces lie in the convex hull of its 1-ring, and they differ
//    by at most its diameter; over a face none of whose vertices lies on a crease made sharp they
//    are equal. The bound at level j is the largest such diameter.
//
//   build/tools/tessera-crease-stand-in ../shared/models/opensubdiv-shapes/catmark_rook.obj --level 6
#include <CLI/CLI.hpp>

#include <opensubdiv/far/primvarRefiner.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/mesh/obj_reader.h"
#include "core/topology/far_topology.h"

namespace {

using namespace tessera;

// A limit position as Far's PrimvarRefiner reads and writes it.
struct Point {
  Vec3d p;
  void Clear(void* = nullptr) { p = Vec3d(); }
  void AddWithWeight(const Point& src, double weight) { p += src.p * weight; }
};

// The mesh with every semi-sharp crease of sharpness ≥ 1 made infinitely sharp; L, the least
// ⌊s⌋ among them (0 when there is none), and the greatest ⌈s⌉.
ControlMesh sharpened(const ControlMesh& mesh, int& least, int& most) {
  ControlMesh out = mesh;
  least = most = 0;
  for (CreaseEdge& c : out.creases) {
    if (c.sharpness < 1 || c.sharpness >= kInfiniteSharpness) continue;
    const int floorS = int(std::floor(c.sharpness));
    least = least == 0 ? floorS : std::min(least, floorS);
    most = std::max(most, int(std::ceil(c.sharpness)));
    c.sharpness = kInfiniteSharpness;
  }
  return out;
}

// Every level's positions, levels concatenated (Far's numbering), and the limit positions of the
// last level.
struct Refined {
  std::vector<Vec3d> points;
  std::vector<Point> limit;
  std::vector<int> levelStart;
};

Refined refineUniformly(Far::TopologyRefiner& refiner, const ControlMesh& mesh, int levels) {
  Far::TopologyRefiner::UniformOptions options(levels);
  options.fullTopologyInLastLevel = true;
  refiner.RefineUniform(options);
  Refined out;
  out.points = refinedPositions(refiner, mesh.positions);
  out.levelStart.push_back(0);
  for (int level = 1; level <= levels; ++level) {
    out.levelStart.push_back(out.levelStart.back() + refiner.GetLevel(level - 1).GetNumVertices());
  }
  std::vector<Point> finest(out.points.size() - size_t(out.levelStart.back()));
  for (size_t v = 0; v < finest.size(); ++v) finest[v].p = out.points[size_t(out.levelStart.back()) + v];
  out.limit.resize(finest.size());
  Far::PrimvarRefinerReal<double> primvar(refiner);
  primvar.Limit(finest, out.limit);
  return out;
}

// The largest 1-ring diameter of a level-j face with a vertex on an edge that is infinitely sharp
// in `sharp` and not in `exact` (a crease made sharp; in `exact` its sharpness is s − j, 0 from
// level s on for an integer s).
double hullBound(const Far::TopologyLevel& exact, const Far::TopologyLevel& sharp, const Vec3d* positions) {
  std::vector<uint8_t> onCrease(size_t(exact.GetNumVertices()), 0);
  for (int e = 0; e < exact.GetNumEdges(); ++e) {
    if (!(sharp.IsEdgeInfSharp(e) && !exact.IsEdgeInfSharp(e))) continue;
    const auto ends = exact.GetEdgeVertices(e);
    onCrease[size_t(ends[0])] = onCrease[size_t(ends[1])] = 1;
  }
  double worst = 0;
  std::vector<int> ring;
  for (int f = 0; f < exact.GetNumFaces(); ++f) {
    const auto corners = exact.GetFaceVertices(f);
    bool touches = false;
    for (int k = 0; k < corners.size(); ++k) touches |= onCrease[size_t(corners[k])] != 0;
    if (!touches) continue;
    ring.clear();
    for (int k = 0; k < corners.size(); ++k) {
      const auto around = exact.GetVertexFaces(corners[k]);
      for (int g = 0; g < around.size(); ++g) {
        const auto vertices = exact.GetFaceVertices(around[g]);
        ring.insert(ring.end(), vertices.begin(), vertices.end());
      }
    }
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    for (size_t a = 0; a < ring.size(); ++a) {
      for (size_t b = a + 1; b < ring.size(); ++b) {
        worst = std::max(worst, length(positions[size_t(ring[a])] - positions[size_t(ring[b])]));
      }
    }
  }
  return worst;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"How far the limit surface moves when its semi-sharp creases are made infinitely sharp: "
               "measured, and the hull bound at each level"};
  std::string path;
  int levels = 6;
  app.add_option("mesh", path, "OBJ with crease tags")->required();
  app.add_option("--level", levels, "Uniform level J of the measurement")->check(CLI::Range(1, 9));
  CLI11_PARSE(app, argc, argv);

  const ControlMesh mesh = readObjFile(path);
  int least = 0, most = 0;
  const ControlMesh sharp = sharpened(mesh, least, most);
  if (least == 0) {
    std::printf("%s: no semi-sharp crease of sharpness 1 or more\n", path.c_str());
    return 0;
  }
  // Far's limit masks are exact once no semi-sharp edge is left: below that level they take a
  // crease with sharpness left as sharp, and the two surfaces would read the same.
  if (levels < most) {
    std::fprintf(stderr, "%s: --level %d is below the creases' sharpness %d: the limit positions there are not exact\n",
                 path.c_str(), levels, most);
    return 2;
  }
  Vec3 lo, hi;
  mesh.bounds(lo, hi);
  const double diagonal = length(Vec3d(hi) - Vec3d(lo));
  const auto exactRefiner = createTopologyRefiner(mesh), sharpRefiner = createTopologyRefiner(sharp);
  const Refined exact = refineUniformly(*exactRefiner, mesh, levels);
  const Refined stand = refineUniformly(*sharpRefiner, sharp, levels);
  double measured = 0;
  for (size_t v = 0; v < exact.limit.size(); ++v) measured = std::max(measured, length(exact.limit[v].p - stand.limit[v].p));
  std::printf("%s: diagonal %.6g, creases made sharp from L = %d, measured at level %d: %.4g (%.3g of the diagonal)\n",
              path.c_str(), diagonal, least, levels, measured, measured / diagonal);
  bool sound = true;
  for (int j = 0; j <= std::min(levels, least); ++j) {
    // Up to L levels the two rule sets make the same points.
    double apart = 0;
    for (int v = exact.levelStart[size_t(j)]; v < (j < levels ? exact.levelStart[size_t(j) + 1] : int(exact.points.size())); ++v) {
      apart = std::max(apart, length(exact.points[size_t(v)] - stand.points[size_t(v)]));
    }
    const double bound = hullBound(exactRefiner->GetLevel(j), sharpRefiner->GetLevel(j), exact.points.data() + exact.levelStart[size_t(j)]);
    sound = sound && measured <= bound && apart == 0;
    std::printf("  level %d: hull bound %.4g (%.3g of the diagonal, %.1f x measured); points apart %.3g\n", j, bound,
                bound / diagonal, measured > 0 ? bound / measured : 0.0, apart);
  }
  std::printf("  %s\n", sound ? "every bound holds" : "A BOUND FAILS");
  return sound ? 0 : 1;
}
