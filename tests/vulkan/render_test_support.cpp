#include "render_test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>

namespace tessera::gpu::testing {
namespace {

Vec3d lerp(const Vec3d& a, const Vec3d& b, double t) {
  return a * (1.0 - t) + b * t;
}

Vec3d normalized(const Vec3d& v) {
  return v * (1.0 / length(v));
}

Vec3 toFloat(const Vec3d& v) {
  return Vec3(float(v.x), float(v.y), float(v.z));
}

bool lexLess(const Vec3& a, const Vec3& b) {
  if (a.x != b.x) return a.x < b.x;
  if (a.y != b.y) return a.y < b.y;
  return a.z < b.z;
}

// Cubic Bézier approximating the great-circle arc from a to b on the sphere (centre, radius):
// inner points along the end tangents at 4/3·tan(θ/4). Computed from the lexicographically
// smaller end, so both patches sharing the arc get the same floats.
std::array<Vec3, 4> arc(const Vec3& a, const Vec3& b, const Vec3d& centre, double radius) {
  if (lexLess(b, a)) {
    std::array<Vec3, 4> r = arc(b, a, centre, radius);
    return {r[3], r[2], r[1], r[0]};
  }
  Vec3d pa = (Vec3d(a) - centre) * (1.0 / radius);
  Vec3d pb = (Vec3d(b) - centre) * (1.0 / radius);
  double c = std::clamp(dot(pa, pb), -1.0, 1.0);
  double theta = std::acos(c);
  double kappa = 4.0 / 3.0 * std::tan(theta / 4.0);
  Vec3d ta = normalized(pb - pa * c);
  Vec3d tb = normalized(pa - pb * c);
  return {a, toFloat(centre + (pa + ta * kappa) * radius),
          toFloat(centre + (pb + tb * kappa) * radius), b};
}

// Bilinearly blended Coons patch of four cubic boundaries, as a bicubic Bézier net:
// ruled surface in v + ruled surface in u − bilinear corners, each degree-raised to cubic.
void fillCoonsInterior(std::array<Vec3d, 16>& p) {
  auto at = [&](int i, int j) -> Vec3d& { return p[4 * j + i]; };
  for (int j = 1; j <= 2; ++j) {
    for (int i = 1; i <= 2; ++i) {
      double s = i / 3.0;
      double t = j / 3.0;
      Vec3d ruledV = at(i, 0) * (1 - t) + at(i, 3) * t;
      Vec3d ruledU = at(0, j) * (1 - s) + at(3, j) * s;
      Vec3d corners = at(0, 0) * ((1 - s) * (1 - t)) + at(3, 0) * (s * (1 - t)) +
                      at(0, 3) * ((1 - s) * t) + at(3, 3) * (s * t);
      at(i, j) = ruledV + ruledU - corners;
    }
  }
}

// Edge-function rasterisation of one triangle at pixel centres (inclusive edges).
void rasterizeTriangle(const double (&x)[3], const double (&y)[3], uint32_t w, uint32_t h,
                       std::vector<uint8_t>& mask) {
  double area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
  if (area == 0.0) return;
  double sign = area > 0 ? 1.0 : -1.0;
  int x0 = std::max(0, int(std::floor(std::min({x[0], x[1], x[2]}) - 0.5)));
  int x1 = std::min(int(w) - 1, int(std::ceil(std::max({x[0], x[1], x[2]}))));
  int y0 = std::max(0, int(std::floor(std::min({y[0], y[1], y[2]}) - 0.5)));
  int y1 = std::min(int(h) - 1, int(std::ceil(std::max({y[0], y[1], y[2]}))));
  for (int py = y0; py <= y1; ++py) {
    for (int px = x0; px <= x1; ++px) {
      double cx = px + 0.5;
      double cy = py + 0.5;
      bool inside = true;
      for (int e = 0; e < 3 && inside; ++e) {
        int a = e;
        int b = (e + 1) % 3;
        double edge = (x[b] - x[a]) * (cy - y[a]) - (cx - x[a]) * (y[b] - y[a]);
        inside = edge * sign >= 0.0;
      }
      if (inside) mask[size_t(py) * w + px] = 1;
    }
  }
}

}  // namespace

RenderPatch makePatch(const ControlNet& net, std::array<uint32_t, 4> edgeLevels, uint32_t id) {
  RenderPatch p{};
  for (int k = 0; k < 16; ++k) {
    p.controlPoints[k][0] = float(net[k].x);
    p.controlPoints[k][1] = float(net[k].y);
    p.controlPoints[k][2] = float(net[k].z);
  }
  for (int e = 0; e < 4; ++e) p.edgeLevels[e] = edgeLevels[e];
  p.patchId = id;
  return p;
}

Vec3d evalPatch(const RenderPatch& patch, double u, double v) {
  Vec3d rows[4];
  for (int j = 0; j < 4; ++j) {
    Vec3d q[4];
    for (int i = 0; i < 4; ++i) {
      const float* c = patch.controlPoints[4 * j + i];
      q[i] = Vec3d(c[0], c[1], c[2]);
    }
    for (int r = 3; r > 0; --r) {
      for (int i = 0; i < r; ++i) q[i] = lerp(q[i], q[i + 1], u);
    }
    rows[j] = q[0];
  }
  for (int r = 3; r > 0; --r) {
    for (int j = 0; j < r; ++j) rows[j] = lerp(rows[j], rows[j + 1], v);
  }
  return rows[0];
}

std::vector<RenderPatch> makeSphere(const Vec3d& centre, double radius, int k,
                                    const EdgeLevelFn& edgeLevel, uint32_t firstId) {
  struct Face {
    Vec3d n, u, v;
  };
  const Face faces[6] = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
                         {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
                         {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}, {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}}};
  // Cube-lattice coordinates are exact dyadics/ratios computed the same way on every face, so
  // a corner shared by faces maps to the same float point.
  auto corner = [&](const Face& f, int a, int b) {
    double s = -1.0 + 2.0 * a / k;
    double t = -1.0 + 2.0 * b / k;
    Vec3d cube = f.n + f.u * s + f.v * t;
    return toFloat(centre + normalized(cube) * radius);
  };
  std::vector<RenderPatch> patches;
  uint32_t id = firstId;
  for (const Face& f : faces) {
    for (int b = 0; b < k; ++b) {
      for (int a = 0; a < k; ++a) {
        Vec3 c00 = corner(f, a, b), c30 = corner(f, a + 1, b);
        Vec3 c03 = corner(f, a, b + 1), c33 = corner(f, a + 1, b + 1);
        std::array<Vec3, 4> e0 = arc(c00, c30, centre, radius);  // v = 0
        std::array<Vec3, 4> e1 = arc(c30, c33, centre, radius);  // u = 1
        std::array<Vec3, 4> e2 = arc(c03, c33, centre, radius);  // v = 1
        std::array<Vec3, 4> e3 = arc(c00, c03, centre, radius);  // u = 0
        ControlNet net;
        for (int i = 0; i < 4; ++i) {
          net[i] = Vec3d(e0[i]);
          net[12 + i] = Vec3d(e2[i]);
          net[4 * i] = Vec3d(e3[i]);
          net[4 * i + 3] = Vec3d(e1[i]);
        }
        fillCoonsInterior(net);
        std::array<uint32_t, 4> levels = {edgeLevel(c00, c30), edgeLevel(c30, c33),
                                          edgeLevel(c03, c33), edgeLevel(c00, c03)};
        // float → double → float is exact, so boundary points keep the shared arcs' bits.
        patches.push_back(makePatch(net, levels, id++));
      }
    }
  }
  return patches;
}

EdgeLevelFn hashedEdgeLevels(uint32_t lo, uint32_t hi) {
  return [lo, hi](const Vec3& a, const Vec3& b) {
    const Vec3& first = lexLess(a, b) ? a : b;
    const Vec3& second = lexLess(a, b) ? b : a;
    uint32_t h = 2166136261u;
    for (float f : {first.x, first.y, first.z, second.x, second.y, second.z}) {
      uint32_t bits;
      std::memcpy(&bits, &f, 4);
      h = (h ^ bits) * 16777619u;
    }
    return lo + (h >> 8) % (hi - lo + 1);
  };
}

ControlNet planarNet(const Vec3d& corner, const Vec3d& du, const Vec3d& dv) {
  ControlNet net;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) net[4 * j + i] = corner + du * (i / 3.0) + dv * (j / 3.0);
  }
  return net;
}

Pinhole::Pinhole(const Camera& camera) {
  eye_ = Vec3d(camera.eye);
  forward_ = normalized(Vec3d(camera.target) - eye_);
  right_ = normalized(cross(forward_, Vec3d(camera.up)));
  up_ = cross(right_, forward_);
  const double kPi = 3.14159265358979323846;
  focal_ = 0.5 * camera.height / std::tan(0.5 * camera.fovYDegrees * kPi / 180.0);
  cx_ = 0.5 * camera.width;
  cy_ = 0.5 * camera.height;
}

bool Pinhole::project(const Vec3d& p, double& px, double& py) const {
  Vec3d d = p - eye_;
  double z = dot(d, forward_);
  if (z <= 0.0) return false;
  px = cx_ + focal_ * dot(d, right_) / z;
  py = cy_ - focal_ * dot(d, up_) / z;
  return true;
}

bool Pinhole::hitPlaneZ(uint32_t x, uint32_t y, double planeZ, Vec3d& hit) const {
  Vec3d dir = forward_ * focal_ + right_ * (x + 0.5 - cx_) - up_ * (y + 0.5 - cy_);
  if (dir.z == 0.0) return false;
  double t = (planeZ - eye_.z) / dir.z;
  if (t <= 0.0) return false;
  hit = eye_ + dir * t;
  return true;
}

std::vector<uint8_t> rasterizeCoverage(const std::vector<RenderPatch>& patches,
                                       const Camera& camera, int n) {
  Pinhole pinhole(camera);
  std::vector<uint8_t> mask(size_t(camera.width) * camera.height, 0);
  std::vector<double> px((n + 1) * (n + 1)), py((n + 1) * (n + 1));
  for (const RenderPatch& patch : patches) {
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        bool ok = pinhole.project(evalPatch(patch, double(i) / n, double(j) / n),
                                  px[j * (n + 1) + i], py[j * (n + 1) + i]);
        if (!ok) ADD_FAILURE() << "reference scene must lie in front of the camera";
      }
    }
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
        double tx0[3] = {px[a], px[b], px[d]}, ty0[3] = {py[a], py[b], py[d]};
        double tx1[3] = {px[a], px[d], px[c]}, ty1[3] = {py[a], py[d], py[c]};
        rasterizeTriangle(tx0, ty0, camera.width, camera.height, mask);
        rasterizeTriangle(tx1, ty1, camera.width, camera.height, mask);
      }
    }
  }
  return mask;
}

size_t countDropouts(const Frame& frame) {
  size_t count = 0;
  for (uint32_t y = 0; y < frame.height; ++y) {
    for (uint32_t x = 0; x < frame.width; ++x) {
      if (frame.patchIdAt(x, y) != kBackgroundPatchId) continue;
      int covered = 0;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          int qx = int(x) + dx, qy = int(y) + dy;
          if ((dx || dy) && qx >= 0 && qy >= 0 && qx < int(frame.width) && qy < int(frame.height) &&
              frame.patchIdAt(qx, qy) != kBackgroundPatchId) {
            ++covered;
          }
        }
      }
      if (covered >= 5) ++count;
    }
  }
  return count;
}

Renderer makeTestRenderer() {
  DeviceSelection selection = DeviceSelection::fromEnvironment();
  selection.validation = true;
  return Renderer::create(selection);
}

void expectNoValidationMessages(Renderer& renderer) {
  for (const std::string& m : renderer.takeValidationMessages())
    ADD_FAILURE() << "validation: " << m;
}

void dumpFrame(const Frame& frame, const std::string& name) {
  const char* dir = std::getenv("TESSERA_TEST_DUMP_DIR");
  if (!dir || !*dir) return;
  std::ofstream out(std::string(dir) + "/" + name + ".ppm", std::ios::binary);
  out << "P6\n" << frame.width << " " << frame.height << "\n255\n";
  for (size_t i = 0; i < size_t(frame.width) * frame.height; ++i) {
    out.write(reinterpret_cast<const char*>(&frame.rgba[4 * i]), 3);
  }
}

}  // namespace tessera::gpu::testing
