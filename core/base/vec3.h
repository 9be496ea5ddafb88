// Minimal 3-vector used by the geometry core and, through TESSERA_HD, by the CUDA kernels.
#pragma once

#include <cmath>

#include "core/base/host_device.h"

namespace tessera {

template <typename T>
struct Vec3T {
  T x{}, y{}, z{};

  Vec3T() = default;  // defaulted: host-device for CUDA without an annotation
  TESSERA_HD Vec3T(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
  template <typename U>
  TESSERA_HD explicit Vec3T(const Vec3T<U>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}

  TESSERA_HD Vec3T operator+(const Vec3T& o) const { return {x + o.x, y + o.y, z + o.z}; }
  TESSERA_HD Vec3T operator-(const Vec3T& o) const { return {x - o.x, y - o.y, z - o.z}; }
  TESSERA_HD Vec3T operator*(T s) const { return {x * s, y * s, z * s}; }
  TESSERA_HD Vec3T& operator+=(const Vec3T& o) {
    x += o.x, y += o.y, z += o.z;
    return *this;
  }
  TESSERA_HD T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

template <typename T>
TESSERA_HD Vec3T<T> operator*(T s, const Vec3T<T>& v) {
  return v * s;
}
template <typename T>
TESSERA_HD T dot(const Vec3T<T>& a, const Vec3T<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <typename T>
TESSERA_HD Vec3T<T> cross(const Vec3T<T>& a, const Vec3T<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <typename T>
TESSERA_HD T length(const Vec3T<T>& v) {
  return std::sqrt(dot(v, v));
}
// ‖v‖²: a maximum of lengths is the square root of the maximum of these, bit for bit (sqrt is
// correctly rounded, so monotone), with one square root instead of one per length.
template <typename T>
TESSERA_HD T lengthSquared(const Vec3T<T>& v) {
  return dot(v, v);
}

using Vec3 = Vec3T<float>;
using Vec3d = Vec3T<double>;

}  // namespace tessera
