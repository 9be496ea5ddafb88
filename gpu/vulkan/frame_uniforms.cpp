#include "gpu/vulkan/frame_uniforms.h"

#include <algorithm>
#include <cmath>

namespace tessera::gpu {
namespace {

void set4(float out[4], const Vec3& v, float w) {
  out[0] = v.x;
  out[1] = v.y;
  out[2] = v.z;
  out[3] = w;
}

}  // namespace

FrameUniforms makeFrameUniforms(const Camera& camera, const ViewProjection& vp,
                                const RenderOptions& options) {
  FrameUniforms u{};
  std::copy(vp.matrix.begin(), vp.matrix.end(), u.viewProj);
  set4(u.eye, camera.eye, 1.0f);
  const Light& light = options.light;
  set4(u.lightDirection, light.direction, light.headlight ? 1.0f : 0.0f);
  set4(u.lightColor, light.color, 1.0f);
  const Material& m = options.material;
  set4(u.ambientColor, m.ambient, 1.0f);
  set4(u.diffuseColor, m.diffuse, 1.0f);
  set4(u.specularColor, m.specular, m.shininess);
  return u;
}

}  // namespace tessera::gpu
