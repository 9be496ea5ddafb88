// Shared pieces of the renderer tests: scenes with known geometry, an independent CPU
// reference (double-precision Bézier evaluation, a pinhole projection written apart from
// gpu/vulkan/camera_math, a tiny rasterizer), pixel counters and a debug PPM writer.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/base/vec3.h"
#include "gpu/vulkan/renderer.h"

namespace tessera::gpu::testing {

using ControlNet = std::array<Vec3d, 16>;  // row-major, as RenderPatch

RenderPatch makePatch(const ControlNet& net, std::array<uint32_t, 4> edgeLevels, uint32_t id);

// Surface point by de Casteljau in double precision (not the GPU's Bernstein form).
Vec3d evalPatch(const RenderPatch& patch, double u, double v);

// A sphere made of 6 cube faces × k×k bicubic patches. Every patch edge is a cubic
// approximation of a great-circle arc computed from its two end points in a canonical order,
// so neighbours share bit-identical boundary control points; interiors are bicubic Coons
// patches. `edgeLevel(a, b)` gives the level of the edge between corners a and b and must be
// symmetric in its arguments.
using EdgeLevelFn = std::function<uint32_t(const Vec3&, const Vec3&)>;
std::vector<RenderPatch> makeSphere(const Vec3d& centre, double radius, int k,
                                    const EdgeLevelFn& edgeLevel, uint32_t firstId);

// Symmetric pseudo-random edge levels in [lo, hi], from the bits of the end points.
EdgeLevelFn hashedEdgeLevels(uint32_t lo, uint32_t hi);

// A planar patch over the parallelogram corner + s*du + t*dv, (s,t) in [0,1]² (bilinear).
ControlNet planarNet(const Vec3d& corner, const Vec3d& du, const Vec3d& dv);

// Pinhole camera, independent of the renderer's matrices: pixel (0,0) is the top-left pixel,
// its centre at (0.5, 0.5).
class Pinhole {
 public:
  explicit Pinhole(const Camera& camera);
  // False when p is not in front of the camera.
  bool project(const Vec3d& p, double& px, double& py) const;
  // Where the ray through pixel centre (x + 0.5, y + 0.5) meets the plane z = planeZ.
  bool hitPlaneZ(uint32_t x, uint32_t y, double planeZ, Vec3d& hit) const;

 private:
  Vec3d eye_, right_, up_, forward_;
  double focal_;
  double cx_, cy_;
};

// Coverage of the patches' surfaces (each sampled on an n×n grid, in double precision),
// rasterised at pixel centres: 1 where covered.
std::vector<uint8_t> rasterizeCoverage(const std::vector<RenderPatch>& patches,
                                       const Camera& camera, int n);

// Background pixels most (≥ 5) of whose 8 neighbours are covered: the paper's dropouts.
size_t countDropouts(const Frame& frame);

// Renderer for tests: device from the environment (TESSERA_VK_DEVICE), validation requested
// (used when the layer is installed). checkNoValidationMessages fails the test on any message.
Renderer makeTestRenderer();
void expectNoValidationMessages(Renderer& renderer);

// Writes frame as PPM into $TESSERA_TEST_DUMP_DIR when that is set (debugging only).
void dumpFrame(const Frame& frame, const std::string& name);

}  // namespace tessera::gpu::testing
