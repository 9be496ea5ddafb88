// Meshlet tiling for the mesh-shader path (VK_EXT_mesh_shader). A meshlet is a run of
// kMeshletTriangles consecutive triangles of one patch's pattern (tess_pattern.glsl), emitted
// with three vertices each: 64 triangles, 192 vertices, inside the spec minimum of 256/256 for
// maxMeshOutputPrimitives/Vertices (the renderer checks the device's limits before using it).
// A task workgroup handles kTaskPatches patches: it culls them and launches their meshlets.
#ifndef TESSERA_MESHLET_LAYOUT_GLSL
#define TESSERA_MESHLET_LAYOUT_GLSL

const uint kMeshletTriangles = 64u;
const uint kMeshletVertices = 3u * kMeshletTriangles;
const uint kTaskPatches = 32u;
const uint kMeshThreads = 32u;

// What a task workgroup hands its meshlets: the first patch of the group and, per patch, the
// index of its first meshlet (exclusive prefix sum; entry kTaskPatches is the total).
struct TaskPayload {
  uint firstPatch;
  uint firstMeshlet[kTaskPatches + 1u];
};

#endif
