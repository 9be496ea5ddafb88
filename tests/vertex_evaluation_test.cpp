// core/stitching/vertex_evaluation.h's seam, which the CUDA engine plugs into: an evaluation that puts every
// vertex on the surface itself (here SurfaceEvaluator, in reverse order, into poisoned arrays)
// gives the CPU path's mesh and per-vertex records exactly; one that declines (a device out of
// memory) leaves the CPU to do it, with the same result; copies get their original's position.
#include <gtest/gtest.h>

#include <limits>

#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "core/pipeline/tessellate.h"
#include "core/stitching/vertex_evaluation.h"
#include "core/surface/adaptive_surface.h"
#include "core/surface/surface_evaluation.h"
#include "reference/models.h"
#include "tests/support/mesh_equality.h"

namespace tessera {
namespace {

class ReverseEvaluation : public VertexEvaluation {
 public:
  ReverseEvaluation(const PatchSet& patches, bool decline) : patches_(patches), decline_(decline) {}
  bool evaluate(const AdaptivePlan& plan, const Stitching& stitching, std::vector<Vec3>& positions,
                std::vector<Vec3>& normals) override {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::fill(positions.begin(), positions.end(), Vec3(nan, nan, nan));
    std::fill(normals.begin(), normals.end(), Vec3(nan, nan, nan));
    ++calls;
    if (decline_) return false;
    SurfaceEvaluator evaluator(patches_.adaptive->tree, patches_);
    for (size_t i = stitching.vertices.size(); i-- > 0;) {
      const VertexRequest& request = stitching.vertices[i];
      const SurfaceSample sample = evaluator.evaluate(plan.tiles[request.tile].node, request.u, request.v);
      positions[i] = Vec3(sample.position), normals[i] = Vec3(sample.normal);
    }
    return true;
  }
  int calls = 0;

 private:
  const PatchSet& patches_;
  bool decline_;
};

TEST(VertexEvaluation, AnEvaluationOfItsOwnOrOneThatDeclinesGivesTheCpuMesh) {
  // bigguy: extraordinary vertices, creases none; catmark_cube_creases2: crease copies (one
  // position, a normal per side).
  for (const std::string& path : {testing::modelsDir() + "/bigguy.obj",
                                 testing::modelsDir() + "/opensubdiv-shapes/catmark_cube_creases2.obj"}) {
    SCOPED_TRACE(path);
    const ControlMesh mesh = readObjFile(path);
    const PatchSet patches = buildPatchSet(mesh);
    TessellationOptions options;
    options.accuracy = Accuracy::relative(1e-3);
    options.recordParameters = true;
    const TessellationResult cpu = tessellate(patches, mesh, options);
    for (bool decline : {false, true}) {
      ReverseEvaluation evaluation(patches, decline);
      options.vertexEvaluation = &evaluation;
      const TessellationResult other = tessellate(patches, mesh, options);
      EXPECT_EQ(evaluation.calls, 1);
      EXPECT_EQ(testing::meshDifference(other.mesh, cpu.mesh), "");
    }
  }
}

}  // namespace
}  // namespace tessera
