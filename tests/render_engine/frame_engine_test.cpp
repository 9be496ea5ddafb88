// The frame engine on the test device: requests that must fail and how, cameras that see
// nothing or stand inside the model, the uniform and absolute modes, split pieces, statistics.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <string>
#include <tuple>

#include "core/base/error.h"
#include "gpu/render_engine/render_patches.h"
#include "tests/render_engine/engine_test_support.h"

namespace tessera::testing {
namespace {

using gpu::FrameRequest;
using gpu::kBackgroundPatchId;

FrameRequest smallRequest(const LoadedModel& model) {
  FrameRequest request;
  request.camera = framedCamera(model, {0.3, 0.8, 1}, 40, 256, 256);
  return request;
}

// The request fails with a TesseraError of `kind` whose message contains every one of `words`.
void expectRefused(const FrameRequest& request, ErrorKind kind, std::vector<std::string> words) {
  const LoadedModel& model = loadModel("catmark_edgecorner");
  try {
    testEngine().render(model.patches, request);
    ADD_FAILURE() << "the request was accepted; expected an error mentioning " << words[0];
  } catch (const TesseraError& e) {
    EXPECT_EQ(int(e.kind()), int(kind)) << e.what();
    for (const std::string& w : words) {
      EXPECT_NE(std::string(e.what()).find(w), std::string::npos)
          << "'" << w << "' not in: " << e.what();
    }
  }
}

TEST(FrameEngine, BadCamerasGiveClearErrors) {
  const FrameRequest good = smallRequest(loadModel("catmark_edgecorner"));
  FrameRequest r = good;
  r.camera.eye.x = NAN;
  expectRefused(r, ErrorKind::kInvalidInput, {"camera", "finite"});
  r = good;
  r.camera.target.y = INFINITY;
  expectRefused(r, ErrorKind::kInvalidInput, {"camera", "finite"});
  r = good;
  r.camera.width = 0;
  expectRefused(r, ErrorKind::kInvalidInput, {"width", "got 0"});
  r = good;
  r.camera.height = 0;
  expectRefused(r, ErrorKind::kInvalidInput, {"height", "got 0"});
  r = good;
  r.camera.width = 8193;
  expectRefused(r, ErrorKind::kInvalidInput, {"width", "8193", "8192"});
  r = good;
  r.camera.width = -4;
  expectRefused(r, ErrorKind::kInvalidInput, {"width", "-4"});
  r = good;
  r.camera.fovYDegrees = NAN;
  expectRefused(r, ErrorKind::kInvalidInput, {"fov_y_deg"});
  r = good;
  r.camera.target = r.camera.eye;
  expectRefused(r, ErrorKind::kInvalidInput, {"eye", "target"});
  r = good;
  r.camera.up = r.camera.target - r.camera.eye;
  expectRefused(r, ErrorKind::kInvalidInput, {"up", "parallel"});
  expectNoValidationMessages();
}

TEST(FrameEngine, BadAccuracyAndBudgetsGiveClearErrors) {
  const FrameRequest good = smallRequest(loadModel("catmark_edgecorner"));
  FrameRequest r = good;
  r.accuracy = Accuracy::pixel(0);
  expectRefused(r, ErrorKind::kInvalidInput, {"pixel accuracy"});
  r = good;
  r.eta = 1.5;
  expectRefused(r, ErrorKind::kInvalidInput, {"eta"});
  r = good;
  r.accuracy = Accuracy::absolute(-1);
  expectRefused(r, ErrorKind::kInvalidInput, {"tolerance"});
  r = good;
  r.accuracy = Accuracy::uniformLevel(0);
  expectRefused(r, ErrorKind::kInvalidInput, {"level", "0"});
  r.accuracy = Accuracy::uniformLevel(5000);
  expectRefused(r, ErrorKind::kInvalidInput, {"level", "5000"});
  r = good;
  r.render.uniformLevel = 4;
  expectRefused(r, ErrorKind::kInvalidInput, {"uniformLevel", "Accuracy::uniformLevel"});
  // A tolerance far below what the budget allows: refused before anything is split.
  r = good;
  r.accuracy = Accuracy::absolute(1e-9);
  expectRefused(r, ErrorKind::kLimitExceeded, {"triangles", "budget"});
  r = good;
  r.maxTriangles = 0;
  expectRefused(r, ErrorKind::kInvalidInput, {"budget"});
}

TEST(FrameEngine, CameraLookingAwayGivesABackgroundFrame) {
  const LoadedModel& model = loadModel("bigguy");
  FrameRequest request;
  request.camera = framedCamera(model, {0, 0, 1}, 40, 320, 200);
  request.camera.target = request.camera.eye + (request.camera.eye - model.centre);
  request.render.background = {0.2f, 0.4f, 0.6f, 1.0f};
  gpu::EngineFrame f = testEngine().render(model.patches, request);
  EXPECT_EQ(f.statistics.visiblePieces, 0);
  EXPECT_EQ(f.statistics.triangles, 0u);
  ASSERT_EQ(f.frame.width, 320u);
  ASSERT_EQ(f.frame.height, 200u);
  size_t covered = 0, otherColour = 0;
  for (size_t k = 0; k < f.frame.patchIds.size(); ++k) {
    covered += f.frame.patchIds[k] != kBackgroundPatchId;
    otherColour += f.frame.rgba[4 * k] != 51 || f.frame.rgba[4 * k + 1] != 102 ||
                   f.frame.rgba[4 * k + 2] != 153;
  }
  EXPECT_EQ(covered, 0u);
  EXPECT_EQ(otherColour, 0u);
  expectNoValidationMessages();
}

TEST(FrameEngine, EyeInsideTheModelStillRenders) {
  const LoadedModel& model = loadModel("bigguy");
  FrameRequest request;
  request.camera.eye = model.centre;
  request.camera.target = model.centre + Vec3d(0, 0, 1);
  request.camera.width = 256;
  request.camera.height = 256;
  gpu::EngineFrame f = testEngine().render(model.patches, request);
  EXPECT_GT(f.statistics.visiblePieces, 0);
  EXPECT_LT(f.statistics.visiblePieces, f.statistics.pieces) << "pieces behind the eye are dropped";
  size_t covered = 0;
  for (uint32_t id : f.frame.patchIds) covered += id != kBackgroundPatchId;
  EXPECT_GT(covered, 0u);
  expectNoValidationMessages();
}

// Uniform level p: every piece at p halved per level below the base face (paper Table 2); the
// GPU draws exactly the triangles the CPU counted when nothing is outside the view.
TEST(FrameEngine, UniformLevelsDrawTheCountedTriangles) {
  const LoadedModel& model = loadModel("catmark_edgecorner");
  for (int p : {16, 64, 128}) {
    FrameRequest request = smallRequest(model);
    request.accuracy = Accuracy::uniformLevel(p);
    gpu::EngineFrame f = testEngine().render(model.patches, request);
    int64_t expected = 0, patches = 0, split = 0;
    for (const BezierPiece& piece : f.plan.pieces) {
      EXPECT_EQ(piece.level, std::max(p >> piece.depth, 1));
      int k = gpu::splitCount(piece.level);
      expected += gpu::renderedTriangles(piece.level);
      patches += int64_t(1) << (2 * k);
      split += k > 0;
    }
    EXPECT_EQ(f.statistics.visiblePieces, f.statistics.pieces) << p;
    EXPECT_EQ(f.statistics.plannedTriangles, expected) << p;
    EXPECT_EQ(int64_t(f.statistics.triangles), expected) << p;
    EXPECT_EQ(f.statistics.renderPatches, patches) << p;
    EXPECT_EQ(f.statistics.splitPieces, split) << p;
    EXPECT_EQ(f.statistics.gpuCulledPatches, 0u) << p;
    if (p == 128) {
      EXPECT_GT(split, 0) << "level 128 pieces at depth 0 must be split";
    }
  }
  expectNoValidationMessages();
}

TEST(FrameEngine, AbsoluteToleranceBoundsEveryPiece) {
  const LoadedModel& model = loadModel("catmark_edgecorner");
  FrameRequest request = smallRequest(model);
  request.accuracy = Accuracy::absolute(1e-3 * 2 * model.radius);
  gpu::EngineFrame f = testEngine().render(model.patches, request);
  EXPECT_LE(f.statistics.guaranteedBound, request.accuracy.tolerance);
  EXPECT_GT(f.statistics.triangles, 0u);
  // A ten times tighter tolerance needs about √10 times the level, ten times the triangles.
  FrameRequest tighter = request;
  tighter.accuracy.tolerance /= 10;
  gpu::EngineFrame g = testEngine().render(model.patches, tighter);
  EXPECT_GT(g.statistics.plannedTriangles, 5 * f.statistics.plannedTriangles);
  expectNoValidationMessages();
}

// Sub-pieces of one split piece, tessellated by the renderer: welded by exact position bits, only
// the piece's outer boundary is left open (4 sides × 4 sub-pieces × 50 segments).
TEST(FrameEngine, SplitPieceIsWatertightInsideOnTheGpu) {
  BezierPiece piece;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      piece.bezier[size_t(4 * j + i)] = Vec3(i * 0.37f, j * 0.41f, std::sin(float(i * j)) * 0.5f);
    }
  }
  piece.level = 200;
  std::vector<gpu::RenderPatch> patches;
  gpu::appendRenderPatches(piece, 0, patches);
  ASSERT_EQ(patches.size(), 16u);
  gpu::TessellatedMesh mesh = testEngine().renderer().tessellate(patches);
  std::map<std::tuple<uint32_t, uint32_t, uint32_t>, uint32_t> weld;
  std::vector<uint32_t> id(mesh.positions.size() / 3);
  for (size_t v = 0; v < id.size(); ++v) {
    uint32_t bits[3];
    std::memcpy(bits, &mesh.positions[3 * v], sizeof bits);
    id[v] = weld.emplace(std::make_tuple(bits[0], bits[1], bits[2]), uint32_t(weld.size()))
                .first->second;
  }
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (size_t t = 0; t < mesh.indices.size(); t += 3) {
    for (int e = 0; e < 3; ++e) {
      uint32_t a = id[mesh.indices[t + e]], b = id[mesh.indices[t + (e + 1) % 3]];
      ++edges[{std::min(a, b), std::max(a, b)}];
    }
  }
  int open = 0, overShared = 0;
  for (const auto& [edge, count] : edges) {
    open += count == 1;
    overShared += count > 2;
  }
  EXPECT_EQ(open, 4 * 4 * 50);
  EXPECT_EQ(overShared, 0);
  EXPECT_EQ(mesh.indices.size() / 3, size_t(16 * 2 * 50 * 50));
}

TEST(FrameEngine, ReportsStagesAndRingStatistics) {
  const LoadedModel& model = loadModel("bigguy");
  FrameRequest request;
  request.camera = framedCamera(model, {0.2, 0.1, 1}, 40, 320, 320);
  gpu::EngineFrame f = testEngine().render(model.patches, request);
  const gpu::FrameStatistics& s = f.statistics;
  EXPECT_GT(s.rings, 0);
  EXPECT_GE(s.averageRingDepth, 0);
  EXPECT_LE(s.averageRingDepth, s.maxRingDepth);
  EXPECT_GE(s.averageRingLevel, s.averageRingDepth) << "Far's level comes on top of FAS steps";
  EXPECT_LE(s.averageRingLevel, s.maxRingLevel);
  EXPECT_GT(s.plannedTriangles, 0);
  EXPECT_LE(int64_t(s.triangles), s.plannedTriangles);
  ASSERT_EQ(s.visiblePieces, s.pieces) << "the framed model is entirely in view";
  int64_t patches = 0;
  for (const BezierPiece& piece : f.plan.pieces)
    patches += int64_t(1) << (2 * gpu::splitCount(piece.level));
  EXPECT_EQ(s.renderPatches, patches);
  // Stage times are measured, never compared with a limit here; they must only be sane.
  const gpu::FrameTimings& t = f.timings;
  for (double ms : {t.planMs, t.patchesMs, t.tessellationMs, t.rasterShadingMs, t.crackFillingMs,
                    t.gpuTotalMs, t.renderCallMs}) {
    EXPECT_GE(ms, 0.0);
  }
  EXPECT_GE(t.totalMs, t.planMs + t.patchesMs);
  EXPECT_GE(t.totalMs, t.renderCallMs);
  // Patch ids are plan piece indices.
  size_t foreign = 0;
  for (uint32_t id : f.frame.patchIds)
    foreign += id != kBackgroundPatchId && id >= f.plan.pieces.size();
  EXPECT_EQ(foreign, 0u);
  expectNoValidationMessages();
}

}  // namespace
}  // namespace tessera::testing
