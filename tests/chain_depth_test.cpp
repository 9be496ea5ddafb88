// How deep the surface tree's EV chains go follows the finest tolerance preprocessing is asked
// to serve (core/surface/surface_tree.h, chainFloorFor; docs/ADAPTIVE.md §1a): a tree for a
// coarse tolerance is smaller and serves it with the same tiles as the deepest tree, and a request
// finer than its tree serves is refused rather than answered past ε.
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "core/mesh/obj_reader.h"
#include "core/pipeline/preprocessing.h"
#include "core/pipeline/tessellate.h"
#include "core/surface/adaptive_surface.h"
#include "reference/models.h"

namespace tessera {
namespace {

TessellationOptions relativeOptions(double epsilon) {
  TessellationOptions options;
  options.accuracy = Accuracy::relative(epsilon);
  return options;
}

PatchSet preprocessedFor(const ControlMesh& mesh, double relative) {
  PreprocessingOptions options;
  options.finestRelativeTolerance = relative;
  return buildPatchSet(mesh, options);
}

TEST(ChainDepth, AToleranceGetsAPowerOfTenBelowWhatItNeeds) {
  EXPECT_EQ(chainFloorFor(0), kChainFloor);  // any request
  for (double relative : {0.3, 1e-2, 3e-3, 1e-3, 2e-4, 1e-4, 1e-5, 1e-6}) {
    const double floor = chainFloorFor(relative);
    // Never below the finest floor, which serves every tolerance the server admits.
    EXPECT_LE(floor, std::max(kChainFloor, kChainBuilt * relative) * (1 + 1e-12)) << relative;
    EXPECT_TRUE(floor == kChainFloor || floor > kChainBuilt * relative / 10) << relative;
    EXPECT_GE(floor, kChainFloor) << relative;
  }
}

// Poles, semi-sharp creases and boundaries: chains of several kinds of rings. A shallower chain
// serves with looser stand-ins beside the EV, so a few more triangles there at most.
TEST(ChainDepth, ACoarseTreeIsSmallerAndMakesAtMostOnePercentMoreTriangles) {
  for (const char* name : {"catmark_cubes_semisharp", "catmark_pole8", "catmark_bishop"}) {
    const ControlMesh mesh = readObjFile(testing::modelsDir() + "/opensubdiv-shapes/" + name + ".obj");
    const PatchSet deepest = buildPatchSet(mesh);
    for (double relative : {1e-2, 1e-3}) {
      SCOPED_TRACE(std::string(name) + " at " + std::to_string(relative));
      const PatchSet coarse = preprocessedFor(mesh, relative);
      EXPECT_LT(coarse.adaptive->tree.nodes.size(), deepest.adaptive->tree.nodes.size());
      const TessellationResult a = tessellate(coarse, mesh, relativeOptions(relative));
      const TessellationResult b = tessellate(deepest, mesh, relativeOptions(relative));
      EXPECT_LE(a.summary.guaranteedBound, a.summary.tolerance);
      EXPECT_GE(a.summary.triangles, b.summary.triangles);
      EXPECT_LE(double(a.summary.triangles), 1.01 * double(b.summary.triangles));
    }
  }
}

TEST(ChainDepth, ARequestFinerThanItsTreeIsRefused) {
  const ControlMesh mesh = readObjFile(testing::modelsDir() + "/opensubdiv-shapes/catmark_cubes_semisharp.obj");
  const PatchSet coarse = preprocessedFor(mesh, 1e-2);
  EXPECT_NO_THROW(tessellate(coarse, mesh, relativeOptions(1e-2)));
  EXPECT_NO_THROW(tessellate(coarse, mesh, relativeOptions(5e-3)));
  try {
    tessellate(coarse, mesh, relativeOptions(1e-5));
    ADD_FAILURE() << "a tree for 1e-2 served 1e-5";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("finestRelativeTolerance"), std::string::npos) << e.what();
  }
  // What a request asks is what to preprocess for.
  EXPECT_DOUBLE_EQ(finestRelativeTolerance(mesh, relativeOptions(1e-3)), 1e-3);
}

// Preprocessing is told ε before an encoding's reserve is known (it follows the patch set's box,
// core/pipeline/glb_output.h), and the reserve is planned away from ε: a tree for ε, on a power of
// ten, serves ε less a reserve (the quantized encoding takes at most an eighth of it).
TEST(ChainDepth, AToleranceLessItsEncodingsReserveFindsItsTreeDeepEnough) {
  const ControlMesh mesh = readObjFile(testing::modelsDir() + "/opensubdiv-shapes/catmark_pole8.obj");
  for (double relative : {1e-2, 1e-3}) {
    const PatchSet patches = preprocessedFor(mesh, relative);
    TessellationOptions options = relativeOptions(relative);
    Vec3 lo, hi;
    mesh.bounds(lo, hi);
    options.encodingReserve = 0.125 * relative * length(Vec3d(hi) - Vec3d(lo));
    EXPECT_NO_THROW(tessellate(patches, mesh, options)) << relative;
  }
}

}  // namespace
}  // namespace tessera
