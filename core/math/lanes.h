// Host-only SIMD lanes for geometry written on Vec3d: four doubles (GCC/Clang vector extension,
// AVX2 with the core's flags), and a 3-vector kept in them. Each lane does exactly the operation
// a Vec3d component does, in the same order, so results match Vec3d's bit for bit while a hot
// loop runs one vector instruction per step instead of three scalar ones.
#pragma once

#include "core/base/vec3.h"

namespace tessera {

using Lanes = double __attribute__((vector_size(32)));

// A Vec3d in lanes 0..2: the accumulator evaluateTensorPatch takes on the host. Lane 3 repeats z
// and is never read (filled with 0, GCC clears it with a vmovq form Valgrind 3.19 cannot decode).
struct LaneVec3 {
  Lanes v = {0, 0, 0, 0};

  LaneVec3() = default;
  template <typename T>
  explicit LaneVec3(const Vec3T<T>& p) : v{double(p.x), double(p.y), double(p.z), double(p.z)} {}
  LaneVec3 operator*(double s) const { return LaneVec3(v * s); }
  LaneVec3& operator+=(const LaneVec3& o) {
    v += o.v;
    return *this;
  }
  explicit operator Vec3d() const { return {v[0], v[1], v[2]}; }

 private:
  explicit LaneVec3(Lanes lanes) : v(lanes) {}
};

}  // namespace tessera
