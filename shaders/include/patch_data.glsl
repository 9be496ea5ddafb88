// Patch record as uploaded by gpu/vulkan/patch_batches.cpp (GpuPatch there; std430, 224 bytes).
#ifndef TESSERA_PATCH_DATA_GLSL
#define TESSERA_PATCH_DATA_GLSL

#extension GL_EXT_control_flow_attributes : require

struct GpuPatch {
  float cp[48];  // 16 control points, xyz, row-major as RenderPatch
  uvec4 levels;  // edge levels v=0, u=1, v=1, u=0 (already ≥ 1, uniform mode applied)
  uvec4 info;    // x: patch id, y: first vertex, z: first triangle (batch-relative), w: unused
};

// The including shader declares the patch buffer; this macro reads patch `i`'s points from it
// without first copying the whole record.
#define LOAD_CONTROL_POINTS(buffer, i, cp)                                                  \
  [[unroll]] for (int k_ = 0; k_ < 16; ++k_) {                                              \
    cp[k_] = vec3(buffer[i].cp[3 * k_], buffer[i].cp[3 * k_ + 1], buffer[i].cp[3 * k_ + 2]); \
  }

#endif
