// Plain data in and out of the renderer: the patches to draw, the camera, lighting, options,
// and the frame that comes back. No Vulkan types here, so callers (server, bench) need not
// know the graphics API.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/base/vec3.h"

namespace tessera::gpu {

inline constexpr uint32_t kBackgroundPatchId = 0xFFFFFFFFu;  // reserved: no patch may use it
inline constexpr uint32_t kMaxTargetSize = 8192;             // per side, in pixels
inline constexpr uint32_t kMaxTessellationLevel = 64;        // per edge, as D3D11's limit

// One bicubic Bézier patch to draw.
struct RenderPatch {
  float controlPoints[16][3];  // row-major: index 4*j+i is the point at (u = i/3, v = j/3)
  uint32_t edgeLevels[4];      // edges v=0, u=1, v=1, u=0; each in [1, kMaxTessellationLevel]
  uint32_t patchId;            // written to the patch-ID target; not kBackgroundPatchId
};

// A perspective pinhole camera. nearPlane/farPlane of 0 mean "fit to the patches' bounds".
struct Camera {
  Vec3 eye{0.0f, 0.0f, 5.0f};
  Vec3 target{0.0f, 0.0f, 0.0f};
  Vec3 up{0.0f, 1.0f, 0.0f};
  float fovYDegrees = 45.0f;  // full vertical field of view, in (0, 180)
  uint32_t width = 1920;      // 1 .. kMaxTargetSize
  uint32_t height = 1080;
  float nearPlane = 0.0f;
  float farPlane = 0.0f;
};

// A white headlight (a point light at the eye) unless headlight is false, in which case a
// directional light shines from `direction` (world space, pointing towards the light).
struct Light {
  bool headlight = true;
  Vec3 direction{0.0f, 0.0f, 1.0f};
  Vec3 color{1.0f, 1.0f, 1.0f};
};

// Blinn-Phong material (linear RGB in [0,1]).
struct Material {
  Vec3 ambient{0.08f, 0.08f, 0.09f};
  Vec3 diffuse{0.72f, 0.72f, 0.76f};
  Vec3 specular{0.30f, 0.30f, 0.30f};
  float shininess = 48.0f;
};

enum class GeometryPath {
  kAuto,        // mesh shaders when the device has VK_EXT_mesh_shader, else compute
  kMeshShader,  // task + mesh shaders; an error on devices without them
  kCompute,     // compute tessellation into buffers, then vertex-pulling raster
};

struct RenderOptions {
  GeometryPath path = GeometryPath::kAuto;
  bool crackFilling = true;                                 // paper §6.2.4 post-pass
  std::array<float, 4> background{0.0f, 0.0f, 0.0f, 1.0f};  // RGBA in [0,1]
  uint32_t uniformLevel = 0;  // 0: each patch's own edge levels; p ≥ 1: every level is p
  // Upper bound on the triangles tessellated per geometry batch (compute path), which bounds
  // the vertex/index buffer memory; 0: as many as the device's buffer limits allow.
  uint64_t maxBatchTriangles = 0;
  Light light;
  Material material;
  // Read the patch ids back into Frame::patchIds (tests and tools need them; a server sending
  // images does not, and an 8192 x 8192 frame's are 256 MiB more to copy and hold).
  bool readPatchIds = true;
  // Called between a frame's stages (FrameEngine's planning, every GPU submission: on CPU
  // devices each stage is one, the readback); a caller that wants the frame abandoned (its
  // call cancelled or past its deadline) throws from it, and the exception leaves render() with
  // the renderer ready for its next frame. Null: never asked.
  std::function<void()> checkpoint;
};

// Milliseconds per stage. On GPUs they come from timestamp queries; on CPU implementations
// (lavapipe), whose timestamps misattribute compute work, and on queues without timestamps,
// each stage is a separate submission timed on the host (fromTimestamps = false).
// On the mesh path tessellation runs inside the raster stage: tessellationMs is 0 there.
struct StageTimings {
  double tessellationMs = 0.0;
  double rasterShadingMs = 0.0;
  double crackFillingMs = 0.0;
  double gpuTotalMs = 0.0;   // submission(s) to completion of the frame's GPU work
  double hostTotalMs = 0.0;  // the whole render() call, uploads and readback included
  bool fromTimestamps = false;
};

// A rendered frame, rows top to bottom. patchIds holds kBackgroundPatchId where nothing was
// drawn; depth is window depth in [0,1] (1 = far plane / background).
struct Frame {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<uint8_t> rgba;       // 4 bytes per pixel
  std::vector<uint32_t> patchIds;  // one per pixel
  std::vector<float> depth;        // one per pixel
  StageTimings timings;
  GeometryPath pathUsed = GeometryPath::kCompute;
  uint32_t patchesCulled = 0;       // by the frustum test
  uint64_t trianglesGenerated = 0;  // by the patches that were not culled
  uint32_t batches = 0;             // geometry batches the patches were split into

  uint32_t patchIdAt(uint32_t x, uint32_t y) const { return patchIds[size_t(y) * width + x]; }
};

// The compute path's tessellation of a patch set, read back instead of drawn (no culling).
// Boundary vertices are duplicated per patch, but shared edges have bit-identical positions,
// so welding by exact position gives a watertight mesh where the patches agree on levels.
struct TessellatedMesh {
  std::vector<float> positions;          // xyz per vertex
  std::vector<float> normals;            // xyz per vertex, unit length
  std::vector<uint32_t> vertexPatchIds;  // the patch each vertex belongs to
  std::vector<uint32_t> indices;         // 3 per triangle, counter-clockwise in (u,v)
};

}  // namespace tessera::gpu
