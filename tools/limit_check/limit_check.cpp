// tessera-limit-check: how far a triangle mesh written by someone else (an importer, a modelling
// tool) lies from the exact limit surface of its control cage, and how far its UVs are from
// OpenSubdiv's face-varying evaluation there. For end-to-end tests of clients (the Blender add-on)
// that hold only the mesh they received.
//
//   tessera-limit-check --cage CAGE.obj --mesh MESH.obj [--uv-interpolation all|none|...]
//
// Prints one JSON object: the two-sided distance (reference/limit_distance.h) in object units
// and relative to the cage's diagonal, and its two directions apart (mesh to limit, from samples
// projected onto the limit surface, with the face of the worst; limit to mesh, from a grid on the
// limit domains, which needs no projection); and, when both files have UVs, the largest difference
// between a corner's UV and Bfr's at the limit point its vertex projects to, over corners whose
// vertex projects inside a face (away from its edges by 2 %, where a UV seam could make either
// side's UV the right one). With --far-level L, the mesh to limit direction a second way that
// needs neither Bfr nor a projection: each sample's distance to the nearest triangle of Far's
// uniform refinement of the cage at levels L − 1 and L (the refined control mesh, its quads split),
// which converges to the limit surface as L grows (the two levels show how far it has).
#include <algorithm>
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "core/mesh/obj_reader.h"
#include "core/mesh/subdivision_rules.h"
#include "reference/bfr_reference.h"
#include "reference/far_distance.h"
#include "reference/limit_distance.h"
#include "reference/limit_projection.h"
#include "reference/limit_surface.h"

using namespace tessera;

namespace {

struct UvCheck {
  size_t checked = 0;
  double worst = 0;
};

// The limit point nearest to p: from the seed index's nearest samples, each projected in its domain.
testing::LimitPoint nearestLimitPoint(const testing::LimitSurface& surface, const testing::LimitSeedIndex& seeds,
                                      const Vec3d& p) {
  testing::LimitPoint candidates[8], best;
  const int count = seeds.seeds(p, 8, candidates);
  for (int i = 0; i < count; ++i) {
    const testing::LimitPoint reached =
        testing::projectInDomain(surface, p, candidates[i].domain, candidates[i].u, candidates[i].v, 1e-12 * surface.diagonal());
    if (reached.distance < best.distance) best = reached;
  }
  return best;
}

UvCheck checkUvs(const ControlMesh& cage, const testing::LimitSurface& surface, const ControlMesh& mesh) {
  UvCheck check;
  if (!cage.hasUvs() || !mesh.hasUvs()) return check;
  const testing::LimitSeedIndex seeds(surface, 8);
  testing::BfrReference bfr(cage);
  for (size_t corner = 0; corner < mesh.faceVertices.size(); ++corner) {
    const Vec3d p(mesh.positions[size_t(mesh.faceVertices[corner])]);
    const testing::LimitPoint at = nearestLimitPoint(surface, seeds, p);
    if (at.domain < 0 || at.distance > 1e-5 * surface.diagonal()) continue;
    if (std::min({at.u, at.v, 1 - at.u, 1 - at.v}) < 0.02) continue;
    const testing::LimitDomain& domain = surface.domains()[size_t(at.domain)];
    double uv[2];
    if (!bfr.evaluateUv(domain.face, domain.subFace, at.u, at.v, uv)) continue;
    const int i = mesh.uvIndices[corner];
    check.worst = std::max({check.worst, std::abs(uv[0] - mesh.uvs[2 * size_t(i)]), std::abs(uv[1] - mesh.uvs[2 * size_t(i) + 1])});
    ++check.checked;
  }
  return check;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("How far a mesh lies from its cage's limit surface, and its UVs from OpenSubdiv's");
  std::string cagePath, meshPath, rule = "all";
  double reprojectBeyond = -1;
  int farLevel = 0;
  app.add_option("--cage", cagePath, "The control cage (OBJ, with its crease and corner tags)")->required();
  app.add_option("--mesh", meshPath, "The triangle mesh to check (OBJ)")->required();
  app.add_option("--uv-interpolation", rule, "The cage's UV rule (OpenSubdiv's FVAR_LINEAR_*)");
  app.add_option("--reproject-beyond", reprojectBeyond,
                 "A mesh sample whose nearest limit point from the spatial seeds is farther than this fraction "
                 "of the diagonal is projected again from every domain (where the surface folds back, the seeds "
                 "may all lie on another sheet); default: never")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--far-level", farLevel,
                 "Also measure mesh to limit against Far's uniform refinement at this level and the one before")
      ->check(CLI::Range(2, 10));
  CLI11_PARSE(app, argc, argv);
  try {
    ControlMesh cage = readObjFile(cagePath);
    const std::optional<UvInterpolation> uvRule = parseUvInterpolation(rule);
    if (!uvRule) throw std::invalid_argument("unknown --uv-interpolation " + rule);
    cage.rules.uvInterpolation = *uvRule;
    const ControlMesh mesh = readObjFile(meshPath);
    const testing::LimitSurface surface(cage);
    testing::TriangleMeshView view;
    view.positions = mesh.positions;
    std::vector<uint32_t> indices(mesh.faceVertices.begin(), mesh.faceVertices.end());
    for (int size : mesh.faceSizes) {
      if (size != 3) throw std::invalid_argument(meshPath + " has a face of " + std::to_string(size) + " vertices; triangles only");
    }
    view.indices = indices;
    testing::LimitDistanceOptions options;
    if (reprojectBeyond >= 0) options.everyDomainBeyond = reprojectBeyond * surface.diagonal();
    const testing::LimitDistanceReport report = testing::measureLimitDistance(surface, view, options);
    const UvCheck uvs = checkUvs(cage, surface, mesh);
    std::string far;
    if (farLevel > 0) {
      char text[160];
      std::snprintf(text, sizeof text, ", \"farLevel\": %d, \"meshToFar\": %.9g, \"meshToFarCoarser\": %.9g", farLevel,
                    testing::distanceToFarRefinement(cage, farLevel, view),
                    testing::distanceToFarRefinement(cage, farLevel - 1, view));
      far = text;
    }
    std::printf("{\"twoSided\": %.9g, \"relative\": %.9g, \"diagonal\": %.9g, \"triangles\": %zu, "
                "\"uvCornersChecked\": %zu, \"uvWorst\": %.9g, \"meshToLimit\": %.9g, \"limitToMesh\": %.9g, "
                "\"meshToLimitFace\": %d, \"limitToMeshFace\": %d, \"trianglesReprojected\": %zu%s}\n",
                report.twoSided(), report.twoSidedRelative(), report.diagonal, indices.size() / 3, uvs.checked, uvs.worst,
                report.meshToLimit, report.limitToMesh, report.meshToLimitAt.face, report.limitToMeshAt.face,
                report.trianglesReprojected, far.c_str());
  } catch (const std::exception& error) {
    std::fprintf(stderr, "tessera-limit-check: %s\n", error.what());
    return 1;
  }
  return 0;
}
