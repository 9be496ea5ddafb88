// KHR_mesh_quantization for positions: each coordinate a 16-bit integer q over the control mesh's
// box, the glTF node's translation c and uniform scale s mapping it back (p ≈ c + s q). The
// limit surface lies in the control points' convex hull, hence in their box, so the grid is
// known before tessellating and its error can be set aside from ε (docs/GLB.md).
#pragma once

#include <array>
#include <cstdint>

#include "core/base/vec3.h"

namespace tessera {

struct PositionQuantization {
  Vec3d center;     // c, float-representable: what a viewer's float32 translation holds
  double step = 1;  // s, float-representable
  // Bound on |c + s q − p| as a viewer computes it in float32, for every p in the box:
  // √3 (s/2 + 2⁻²³ M) with M the largest |c_i| plus half the box (docs/GLB.md).
  double maxError = 0;

  std::array<int16_t, 3> quantize(const Vec3& p) const;
  Vec3 dequantize(const std::array<int16_t, 3>& q) const;  // in float, as a viewer does
};

PositionQuantization quantizationForBox(const Vec3& lo, const Vec3& hi);

}  // namespace tessera
