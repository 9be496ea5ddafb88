// Pixel-accurate frames against an independent reference of the exact limit surface: a dense
// Bfr mesh (reference_surface.h), rasterised on the CPU for coverage and drawn through the same
// Vulkan shading for colour. 512×512, crack filling on, 2-3 views per model.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <ostream>
#include <string>

#include "tests/render_engine/engine_test_support.h"
#include "tests/render_engine/reference_surface.h"

namespace tessera::testing {
namespace {

using gpu::kBackgroundPatchId;

constexpr int kSize = 512;

// The reference's own error must stay well under the half pixel the engine is allowed, so that
// a disagreement is the engine's: its triangles within 0.1 px of the surface (silhouettes), the
// vertices of its shading patches within half of these (0.05 px, 0.25°) of Bfr's points and
// normals (shadingReference drops cells that are not).
constexpr double kMaxReferenceError = 0.1;
constexpr double kMaxReferenceNormalDegrees = 0.5;
// Grid cells per face: 16, doubled on the faces in view (up to 256) until the reference is
// within kMaxReferenceError (close-ups need more). The shading reference uses at least 4×4
// Hermite cells per face, at level G/4 ≤ 64.
constexpr int kCoarseCells = 16, kMaxCells = 256, kHermiteCells = 4;

struct ViewCase {
  const char* model;
  const char* view;
  Vec3d direction;
  double fovYDegrees;
  Vec3d targetOffset;  // in radii of the model's bounding sphere
  double zoom;
  // A telephoto detail of that view: the field of view narrowed `narrow` times around the ray
  // through the point at fractions `aim` of the width and height (1 and the centre: none).
  double narrow = 1;
  double aim[2] = {0.5, 0.5};
};

std::string caseName(const ViewCase& c) {
  return std::string(c.model) + "_" + c.view;
}
void PrintTo(const ViewCase& c, std::ostream* os) {
  *os << caseName(c);
}

const ViewCase kCases[] = {
    {"bigguy", "front", {0, 0, 1}, 40, {}, 1.5},
    {"bigguy", "above_left", {-1, 0.8, 0.7}, 40, {}, 1.5},
    {"bigguy", "close", {0.5, 0.2, 1}, 20, {0.1, 0.3, 0}, 3},
    // Levels above 64 (split pieces) on a silhouette of the head.
    {"bigguy", "telephoto", {0.5, 0.2, 1}, 20, {0.1, 0.3, 0}, 3, 200, {0.754, 0.215}},
    {"monsterfrog", "front", {0, 0.2, 1}, 40, {}, 1.5},
    {"monsterfrog", "side_below", {1, -0.5, -0.3}, 40, {}, 1.5},
    {"monsterfrog", "close", {-0.6, 0.4, 1}, 20, {0.0, 0.1, 0.3}, 3},
    {"catmark_edgecorner", "oblique", {0.4, 1, 0.9}, 40, {}, 1.2},
    {"catmark_edgecorner", "grazing", {1, 0.15, 0.3}, 40, {}, 1.2},
};

struct Comparison {
  gpu::EngineFrame frame;  // the engine, crack filling on
  size_t dropoutsWithoutFilling = 0;
  int cells = 0;
  double referenceError = 0;  // pixels
  ShadingReference shading;
  CpuRaster cpu;                 // reference coverage
  std::vector<uint8_t> refRgba;  // reference through the renderer
  std::vector<uint8_t> refCovered;
};

// Background pixels of `ids` inside the reference's silhouette whose 4 neighbours are covered.
size_t countDropouts(const std::vector<uint32_t>& ids, const CpuRaster& cpu) {
  size_t count = 0;
  const int w = cpu.width;
  for (int y = 1; y + 1 < cpu.height; ++y) {
    for (int x = 1; x + 1 < w; ++x) {
      size_t k = size_t(y) * w + x;
      if (ids[k] != kBackgroundPatchId || !cpu.covered[k]) continue;
      count += ids[k - 1] != kBackgroundPatchId && ids[k + 1] != kBackgroundPatchId &&
               ids[k - w] != kBackgroundPatchId && ids[k + w] != kBackgroundPatchId;
    }
  }
  return count;
}

// The reference drawn by the renderer with fixed planes, in chunks any device can take, the
// nearest fragment of all chunks kept per pixel. Crack filling off: it is the thing tested.
void renderReference(const gpu::Camera& camera, Comparison& out) {
  const std::vector<gpu::RenderPatch>& patches = out.shading.patches;
  gpu::RenderOptions options;
  options.crackFilling = false;
  const size_t pixels = size_t(camera.width) * camera.height;
  out.refRgba.assign(4 * pixels, 0);
  out.refCovered.assign(pixels, 0);
  std::vector<float> depth(pixels, 2.0f);
  constexpr size_t kChunk = 100'000;
  for (size_t first = 0; first < patches.size(); first += kChunk) {
    size_t count = std::min(kChunk, patches.size() - first);
    gpu::Frame f = testEngine().renderer().render(
        std::span<const gpu::RenderPatch>(patches.data() + first, count), camera, options);
    for (size_t k = 0; k < pixels; ++k) {
      if (f.patchIds[k] == kBackgroundPatchId || f.depth[k] >= depth[k]) continue;
      depth[k] = f.depth[k];
      out.refCovered[k] = 1;
      std::copy_n(&f.rgba[4 * k], 4, &out.refRgba[4 * k]);
    }
  }
}

void dumpComparison(const Comparison& c, const std::string& name) {
  gpu::Frame ref;
  ref.width = ref.height = kSize;
  ref.rgba = c.refRgba;
  dumpFrame(ref, name + "_reference");
  for (size_t k = 0; k < size_t(kSize) * kSize;
       ++k) {  // red: colour difference ×16, green: coverage
    bool a = c.frame.frame.patchIds[k] != kBackgroundPatchId, b = c.refCovered[k] != 0;
    int d = 0;
    for (int ch = 0; ch < 3; ++ch) {
      d = std::max(d, std::abs(int(c.frame.frame.rgba[4 * k + ch]) - int(c.refRgba[4 * k + ch])));
    }
    ref.rgba[4 * k] = uint8_t(a && b ? std::min(255, 16 * d) : 0);
    ref.rgba[4 * k + 1] = uint8_t(a != b ? 255 : 0);
    ref.rgba[4 * k + 2] = uint8_t(a && b ? 40 : 0);
  }
  dumpFrame(ref, name + "_difference");
}

tessera::Camera telephoto(tessera::Camera camera, double narrow, const double (&aim)[2]) {
  Vec3d view = camera.target - camera.eye;
  double distance = length(view);
  Vec3d f = view * (1 / distance);
  Vec3d s = cross(f, camera.up) * (1 / length(cross(f, camera.up)));
  Vec3d u = cross(s, f);
  double tanY = std::tan(camera.fovYDegrees * M_PI / 360);
  double tanX = tanY * camera.width / camera.height;
  camera.target =
      camera.eye + (f + s * ((2 * aim[0] - 1) * tanX) - u * ((2 * aim[1] - 1) * tanY)) * distance;
  camera.fovYDegrees = 360 / M_PI * std::atan(tanY / narrow);
  return camera;
}

const Comparison& comparison(const ViewCase& c) {
  static std::map<std::string, std::unique_ptr<Comparison>> cache;
  static std::map<std::string, std::unique_ptr<ReferenceSurface>> coarse;  // per model
  auto found = cache.find(caseName(c));
  if (found != cache.end()) return *found->second;
  const LoadedModel& model = loadModel(c.model);
  auto out = std::make_unique<Comparison>();
  gpu::FrameRequest request;
  request.camera =
      framedCamera(model, c.direction, c.fovYDegrees, kSize, kSize, c.targetOffset, c.zoom);
  if (c.narrow != 1) request.camera = telephoto(request.camera, c.narrow, c.aim);
  out->frame = testEngine().render(model.patches, request);

  // The reference camera: the same pinhole with planes that hold the whole model (every test
  // eye is outside the bounding sphere).
  gpu::Camera camera;
  camera.eye = Vec3(request.camera.eye);
  camera.target = Vec3(request.camera.target);
  camera.up = Vec3(request.camera.up);
  camera.fovYDegrees = float(request.camera.fovYDegrees);
  camera.width = camera.height = kSize;
  double distance = length(model.centre - request.camera.eye);
  camera.nearPlane = float(0.5 * (distance - model.radius));
  camera.farPlane = float(2.0 * (distance + model.radius));
  Pinhole pinhole(camera, camera.nearPlane, camera.farPlane);

  auto& reference = coarse[c.model];
  if (!reference) {
    reference = std::make_unique<ReferenceSurface>(buildReferenceSurface(model.mesh, kCoarseCells));
  }
  const ReferenceSurface* used = reference.get();
  ReferenceSurface fine;
  out->referenceError = referenceErrorPixels(*used, pinhole);
  if (out->referenceError >= kMaxReferenceError) {
    // Faces the coarse grid puts near the view, allowing for the coarse grid's own error.
    std::vector<uint8_t> inView =
        facesInView(*reference, pinhole, model.mesh.faceCount(), 8.0 + 2 * out->referenceError);
    for (int cells = 2 * kCoarseCells;
         cells <= kMaxCells && out->referenceError >= kMaxReferenceError; cells *= 2) {
      fine =
          buildReferenceSurface(model.mesh, cells, [&](int f) { return inView[size_t(f)] != 0; });
      used = &fine;
      out->referenceError = referenceErrorPixels(fine, pinhole);
    }
  }
  out->cells = used->cells;
  int hermiteCells = std::max(kHermiteCells, used->cells / int(gpu::kMaxTessellationLevel));
  out->shading = shadingReference(*used, hermiteCells, pinhole, kMaxReferenceError / 2,
                                  kMaxReferenceNormalDegrees / 2);
  out->cpu = rasterizeReference(*used, pinhole, kSize, kSize);
  gpu::FrameRequest unfilled = request;  // for the record: what crack filling repaired
  unfilled.render.crackFilling = false;
  out->dropoutsWithoutFilling =
      countDropouts(testEngine().render(model.patches, unfilled).frame.patchIds, out->cpu);
  renderReference(camera, *out);
  expectNoValidationMessages();
  dumpFrame(out->frame.frame, caseName(c));
  dumpComparison(*out, caseName(c));
  return *(cache[caseName(c)] = std::move(out));
}

class ReferenceComparison : public ::testing::TestWithParam<ViewCase> {};

TEST_P(ReferenceComparison, SilhouetteMatchesCpuRasterOfBfrMesh) {
  const Comparison& c = comparison(GetParam());
  ASSERT_EQ(c.cpu.clipped, 0u) << "a test camera must keep the reference in front of it";
  ASSERT_LT(c.referenceError, kMaxReferenceError) << "reference too coarse for this view";
  const std::vector<uint32_t>& ids = c.frame.frame.patchIds;
  size_t both = 0, either = 0, awayFromEdge = 0;
  const int w = c.cpu.width, h = c.cpu.height;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      size_t k = size_t(y) * w + x;
      bool engine = ids[k] != kBackgroundPatchId, reference = c.cpu.covered[k] != 0;
      both += engine && reference;
      either += engine || reference;
      if (engine == reference) continue;
      // The engine (≤ 0.5 px off) and the reference (< 0.1 px) can disagree only on pixel
      // centres within 0.6 px of the true silhouette, so a mismatch has a reference pixel of the
      // other kind among its 8 neighbours; any other is a hole or a stray piece.
      bool nearEdge = false;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          int qx = x + dx, qy = y + dy;
          if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
          nearEdge |= (c.cpu.covered[size_t(qy) * w + qx] != 0) != reference;
        }
      }
      awayFromEdge += !nearEdge;
    }
  }
  ASSERT_GT(either, 5000u) << "the model should fill a good part of the view";
  double iou = double(both) / double(either);
  std::printf(
      "[ measured ] %s: IoU %.5f (%zu / %zu px), %zu mismatches away from the silhouette; "
      "reference G=%d, %.3f px; pieces %lld (visible %lld, split %lld), max level %d\n",
      caseName(GetParam()).c_str(), iou, both, either, awayFromEdge, c.cells, c.referenceError,
      (long long)c.frame.statistics.pieces, (long long)c.frame.statistics.visiblePieces,
      (long long)c.frame.statistics.splitPieces, c.frame.statistics.maxPieceLevel);
  EXPECT_GE(iou, 0.99);
  EXPECT_EQ(awayFromEdge, 0u);
}

// Thresholds, in 8-bit levels per channel, on pixels covered in both frames:
// - Smooth pixels (3×3 neighbourhood covered in both, reference varying by ≤ 8 levels there):
//   mean below 1.0. Two independently rounded colours differ by 1/3 level on average; the rest
//   allows normals off by about 0.2° on average (diffuse 0.72·255 levels per radian). Exact
//   pieces carry the limit's own derivatives, innermost ones (ACC-1) differ slightly.
// - All pixels: mean below 0.6·D + 1/3, D being the reference's mean difference from itself
//   moved by one pixel. The engine's surface is within 0.5 px of the true one and the
//   reference within 0.1 px, so near silhouettes, occlusions and highlights the engine's image
//   is the reference displaced by at most 0.6 px, which changes it by about 0.6 of what a whole
//   pixel does (linear in the displacement, for gradients and for edge pixels alike).
TEST_P(ReferenceComparison, ShadingMatchesBfrMeshThroughSameRenderer) {
  const Comparison& c = comparison(GetParam());
  const std::vector<uint8_t>& rgba = c.frame.frame.rgba;
  const std::vector<uint32_t>& ids = c.frame.frame.patchIds;
  const int w = kSize;
  auto covered = [&](size_t k) { return ids[k] != kBackgroundPatchId && c.refCovered[k]; };
  auto difference = [&](const std::vector<uint8_t>& a, size_t k, const std::vector<uint8_t>& b,
                        size_t q) {
    double d = 0;
    for (int ch = 0; ch < 3; ++ch) d += std::abs(int(a[4 * k + ch]) - int(b[4 * q + ch]));
    return d / 3;
  };
  double all = 0, smooth = 0, shifted = 0;
  size_t allCount = 0, smoothCount = 0, shiftedCount = 0;
  for (int y = 1; y + 1 < w; ++y) {
    for (int x = 1; x + 1 < w; ++x) {
      size_t k = size_t(y) * w + x;
      for (size_t q : {k + 1, k + size_t(w)}) {
        if (c.refCovered[k] && c.refCovered[q]) {
          shifted += difference(c.refRgba, k, c.refRgba, q);
          ++shiftedCount;
        }
      }
      if (!covered(k)) continue;
      double d = difference(rgba, k, c.refRgba, k);
      all += d;
      ++allCount;
      bool isSmooth = true;
      for (int dy = -1; dy <= 1 && isSmooth; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          size_t q = k + dy * w + dx;
          isSmooth &= covered(q) && difference(c.refRgba, q, c.refRgba, k) <= 8;
        }
      }
      if (isSmooth) {
        smooth += d;
        ++smoothCount;
      }
    }
  }
  ASSERT_GT(smoothCount, 1000u);
  double meanAll = all / allCount, meanSmooth = smooth / smoothCount;
  double displaced = shifted / shiftedCount, allowed = 0.6 * displaced + 1.0 / 3.0;
  std::printf(
      "[ measured ] %s: colour MAE %.3f over %zu px (allowed %.3f: reference vs itself "
      "moved 1 px %.3f); smooth pixels %.3f over %zu px (allowed 1.0); shading reference "
      "within %.3f px, %.3f deg (%zu Hermite cells, %zu exact squares)\n",
      caseName(GetParam()).c_str(), meanAll, allCount, allowed, displaced, meanSmooth, smoothCount,
      c.shading.positionPixels, c.shading.normalDegrees, c.shading.hermiteCells,
      c.shading.exactSquares);
  EXPECT_LT(meanSmooth, 1.0);
  EXPECT_LT(meanAll, allowed);
}

TEST_P(ReferenceComparison, NoDropoutWithCrackFilling) {
  const Comparison& c = comparison(GetParam());
  size_t dropouts = countDropouts(c.frame.frame.patchIds, c.cpu);
  std::printf("[ measured ] %s: dropouts %zu with crack filling, %zu without\n",
              caseName(GetParam()).c_str(), dropouts, c.dropoutsWithoutFilling);
  EXPECT_EQ(dropouts, 0u);
}

INSTANTIATE_TEST_SUITE_P(Views, ReferenceComparison, ::testing::ValuesIn(kCases),
                         [](const auto& info) { return caseName(info.param); });

}  // namespace
}  // namespace tessera::testing
